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
//!   balance, fixed values);
//! * a counterweight that is a flat plate of areal density σ within its envelope
//!   ([`CounterweightLimits::plate`]): the plate's convex necessary conditions (the cap bound
//!   on |u|, the rim and disc bounds on I), their curved parts as tangent cones added where
//!   a round's design breaks them (`plate`); the design returned is projected onto the
//!   exact conditions and certified there.
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
//! polished conditions before any SOCP. Where plain Newton fails a round retries it once with
//! proximal steps (`polish::PROX`: a flat direction of the optimum, such as a crank
//! counterweight against an order-1 balancer pair, along which plain Newton drifts off the
//! optimal face); a point so found is certified the same way. Where both fail the loop goes
//! on unchanged.
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
//! `exact_disc = false` always runs clarabel. A goal of several such fields (an operating
//! envelope's scenarios) is one disc over the union of the curves of the fields of the
//! largest scale w·c; the goal's other fields are scanned at the design for V only, so the
//! certificate still bounds the whole goal, and the disc's weights are the optimum's
//! multipliers ([`Multiplier`]).
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
//!
//! # Layout
//! One concern a file, all of them `impl Engine` blocks over the one [`Engine`]: this file
//! the public types and [`solve`]; `assembly` the scales, the scan grid and the cone
//! programs; `exchange_loop` the rounds; `peaks` the true peaks and RMS at a design;
//! `certificate` the lower bounds and the error bounds of a solution; `presolve` the exact
//! disc path; `polish` the Newton polish; `pareto` the fronts; `plate` a plate's conditions
//! and their cutting planes; `validate` the checks. The
//! exchange vocabulary shared with [`crate::synth::counterweight`] is in
//! [`crate::synth::exchange`].

use crate::numeric::Extremum;
use crate::synth::exchange::check_exchange;

/// How a solve ended (the exchange vocabulary shared with `synth::counterweight`).
pub use crate::synth::exchange::Status;
pub use lightest::Lighter;

mod assembly;
mod certificate;
mod constraints;
mod exchange_loop;
mod grid;
mod lightest;
mod pareto;
mod peaks;
mod plate;
mod polish;
mod presolve;
mod rms;
mod validate;

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
    /// A, rows 0 and 1, each of length n: inline up to n = 8 (two counterweights, or one
    /// and a balancer pair), so the millions of values a scan, a polish or an envelope
    /// evaluates allocate nothing.
    pub a: smallvec::SmallVec<[f64; 16]>,
}

impl AffineValue {
    /// All zero, for n variables.
    pub fn zeros(n: usize) -> Self {
        // Inline from a zero buffer (written in place; `from_elem` builds it aside and copies).
        let a = if 2 * n <= 16 {
            smallvec::SmallVec::from_buf_and_len([0.0; 16], 2 * n)
        } else {
            smallvec::smallvec![0.0; 2 * n]
        };
        AffineValue { b: [0.0; 2], a }
    }
    /// Every entry back to zero (a field's `eval` writes into a zeroed value), n kept.
    pub fn clear(&mut self) {
        self.b = [0.0; 2];
        self.a.iter_mut().for_each(|a| *a = 0.0);
    }
    /// n.
    pub fn n(&self) -> usize {
        self.a.len() / 2
    }
    /// Row r of A.
    pub fn row(&self, r: usize) -> &[f64] {
        self.view().row(r)
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
    /// |b + A x|: abs for dim 1, Euclidean for dim 2 (the numbers of [`AffineValue::at`],
    /// its rows read from one slice: the scans ask for it at every grid angle).
    pub fn magnitude(&self, dim: usize, x: &[f64]) -> f64 {
        magnitude(&self.b, &self.a, dim, x)
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

/// |b + A x| of a value with A's rows 0 and 1 in `a` (n entries each): abs for dim 1,
/// Euclidean for dim 2 (an [`AffineValue`]'s and a scan grid's, one function).
fn magnitude(b: &[f64; 2], a: &[f64], dim: usize, x: &[f64]) -> f64 {
    let n = a.len() / 2;
    let v0 = b[0] + dot(&a[..n], x);
    if dim == 2 {
        v0.hypot(b[1] + dot(&a[n..], x))
    } else {
        v0.abs()
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

/// A field the problem does not name, zero, of its dimension (1 or 2): its place in a
/// family's list of fields kept without a field built, where a caller needs the peaks of
/// some fields only (a shape search's candidate asks for its objective's).
pub struct Unused(pub usize);

impl AffineField for Unused {
    fn name(&self) -> &str {
        "unused"
    }
    fn dim(&self) -> usize {
        self.0
    }
    fn eval(&self, _: f64, _: &mut AffineValue) {}
}

/// An unused scalar field (a moment, a torque).
pub static UNUSED_SCALAR: Unused = Unused(1);
/// An unused planar field (a force, a joint load).
pub static UNUSED_PLANAR: Unused = Unused(2);

/// An [`AffineField`] from closures: `eval(θ, out)` and optionally `error(θ, x)`.
pub struct FnField<E, R> {
    /// Name (a literal one is not copied: a family builds its fields per scenario, and
    /// again for each sensitivity).
    pub name: std::borrow::Cow<'static, str>,
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
    pub fn new(name: impl Into<std::borrow::Cow<'static, str>>, dim: usize, eval: E) -> Self {
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
    /// σ, the areal density (kg/m²: density × thickness) of a counterweight that is a flat
    /// plate cut within the envelope ρ (finite, and m_max ≤ σπρ²): the plate's convex
    /// necessary conditions join the constraints (`plate.rs`).
    pub plate: Option<f64>,
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
            plate: None,
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
    /// Uniform angles of RMS values and objectives (even): the least count, doubled while
    /// the field's mean-square form still moves (`rms`, near folds). Default 360.
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
    /// The active maxima at the optimum with their multipliers, when Newton's polish
    /// certified it (empty otherwise): the envelope theorem's weights ([`Multiplier`]).
    #[serde(skip)]
    pub multipliers: Vec<Multiplier>,
    /// Whether Newton's polish found the optimum not isolated: a direction of the design
    /// along which the optimality conditions hold to first order (`polish::flat_design`).
    /// [`Engine::lightest_of_optimum`] then looks for the lightest design of that set.
    #[serde(skip)]
    pub flat: bool,
}

/// An active maximum of the optimum with its multiplier, in the caller's units: the weight
/// of |g_f(θ; x*)| in the optimum's Lagrangian. By the envelope theorem a parameter p that
/// moves the fields (not the design constraints) moves the optimum by
/// dV*/dp = Σ_k `weight`_k ∂|g_{f_k}(θ_k; x*)|/∂p at the design x* and angles θ_k held, and
/// a limit ε_f by dV*/dε_f = −Σ_{k: f_k = f} `weight`_k — where V* is differentiable (unique
/// multipliers; on a tie of maxima with non-unique multipliers these are one of its
/// one-sided derivatives). `weight` = T·λ·c: the objective's multiplier λ (Σλ = 1) times its
/// weight w_f, or a limit's μ scaled back to the objective's unit.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Multiplier {
    /// The field f.
    pub field: usize,
    /// θ_k (rad), the maximum's polished angle.
    pub angle: f64,
    /// The weight (objective's unit per field's unit).
    pub weight: f64,
    /// A bound on its error: Newton's last step in the multiplier, scaled alike.
    pub weight_error: f64,
    /// True for a limit's maximum (|g_f| ≤ ε_f), false for the objective's.
    pub limit: bool,
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
    /// The points, ε increasing: fewer than `requested` when the front stopped (an end or
    /// its last two points spent every exchange round, or an end has no design).
    pub points: Vec<ParetoPoint>,
    /// The number of points asked for.
    pub requested: usize,
}

impl ParetoFront {
    /// Why the front has fewer points than asked, if it has: an end without a design or
    /// that spent every exchange round (no point is computed then), or two last points that
    /// spent every round (the ε after them were not solved).
    pub fn stopped(&self) -> Option<String> {
        if pareto::unusable_end(&self.min_b) || pareto::unusable_end(&self.min_a) {
            return Some(format!(
                "no front point was computed: its ends (the least of each peak alone) ended {:?} ({:?}) and {:?} ({:?}); points between ends that spend every exchange round would each spend as many",
                self.min_b.status, self.min_b.stop, self.min_a.status, self.min_a.stop
            ));
        }
        let last = self.points.last()?;
        (self.points.len() < self.requested).then(|| {
            format!(
                "the front stopped at its point {} of {} (ε = {:.6e}), the second in a row that spent every exchange round ({:?}, {:?}); the {} points after it were not solved",
                self.points.len(),
                self.requested,
                last.eps,
                last.solution.status,
                last.solution.stop,
                self.requested - self.points.len()
            )
        })
    }
}

/// A problem prepared for solving: validated, scaled, its fields cached on the scan grid.
/// Several goals (a Pareto front) share one engine.
pub struct Engine<'p, 'a> {
    pb: &'p Problem<'a>,
    s: Settings,
    n: usize,
    /// Column scales s_j (x = s ⊙ x̂).
    scale: Vec<f64>,
    /// G_f, each field's size over the design box, made on first use (`Engine::g_ref`:
    /// the exact disc path never needs it).
    g_ref: std::sync::OnceLock<Vec<f64>>,
    /// max over the grid of |b_f|: the unbalanced peak (sampled).
    g0: Vec<f64>,
    /// Each field on the scan grid θ_k = 2πk/`scan_samples`.
    grid: Vec<grid::FieldGrid>,
    /// Bounds on |x̂_j| implied by the design constraints (∞ for an unbounded extra).
    xbound: Vec<f64>,
    /// Each field on its RMS grid, built on first use (`rms`).
    rms_grids: Vec<std::sync::OnceLock<rms::RmsGrid>>,
    /// Each counterweight's plate tangents (`plate.rs`), grown by the rounds of every solve
    /// of this engine (each tangent holds for every goal: the plate is the same).
    cuts: std::sync::Mutex<Vec<plate::Cuts>>,
}

/// What `Solution::solver_status` contains when the design and its certificate come from
/// the Newton polish of the optimality conditions.
pub const POLISHED: &str = "optimality conditions polished by Newton";

/// `Solution::solver_status` of a solve by Newton alone from a neighbouring solve (no SOCP).
pub const NEWTON_ONLY: &str =
    "not run: optimality conditions polished by Newton from the neighbouring solve";

/// Solves `pb` with its own goal and limits (an [`Engine`] for one solve).
pub fn solve(pb: &Problem, s: &Settings) -> Result<Solution, MinimaxError> {
    Engine::new(pb, s)?.solve()
}
