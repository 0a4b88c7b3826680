//! The clarabel plumbing shared by the convex engines of `synth/` (the 2-D counterweight
//! SOCP of [`crate::synth::counterweight`] and the general affine minimax of
//! [`crate::synth::minimax`]): a triplet builder for the conic rows and one solve with the
//! tolerance schedule both use.
//!
//! clarabel's standard form is min ½xᵀPx + qᵀx s.t. A x + s = b, s ∈ K. A second-order cone
//! ‖(y₁, …)‖ ≤ y₀ on an affine map y = c + M x is written as the rows s = c − (−M) x, i.e.
//! coefficients −M and right-hand side c, with y₀ first.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

/// A conic program ready for clarabel.
pub(crate) struct Built {
    pub p: CscMatrix<f64>,
    pub q: Vec<f64>,
    pub a: CscMatrix<f64>,
    pub b: Vec<f64>,
    pub cones: Vec<SupportedConeT<f64>>,
}

/// Triplet builder for the conic constraints A x + s = b, s ∈ K.
#[derive(Default)]
pub(crate) struct Rows {
    pub i: Vec<usize>,
    pub j: Vec<usize>,
    pub v: Vec<f64>,
    pub b: Vec<f64>,
    pub cones: Vec<SupportedConeT<f64>>,
}

impl Rows {
    /// One row: s_r = rhs − Σ coeffs·x (zero coefficients dropped).
    pub fn row(&mut self, coeffs: &[(usize, f64)], rhs: f64) {
        let r = self.b.len();
        for &(j, v) in coeffs {
            if v != 0.0 {
                self.i.push(r);
                self.j.push(j);
                self.v.push(v);
            }
        }
        self.b.push(rhs);
    }

    /// The program over `n` variables with the objective ½xᵀPx + qᵀx.
    pub fn build(self, n: usize, p: CscMatrix<f64>, q: Vec<f64>) -> Built {
        let m = self.b.len();
        let a = CscMatrix::new_from_triplets(m, n, self.i, self.j, self.v);
        Built {
            p,
            q,
            a,
            b: self.b,
            cones: self.cones,
        }
    }
}

const PRECISE_REFINE: u32 = 40;
const PRECISE_REG: f64 = 1e-12;

/// What one clarabel solve returned.
pub(crate) struct ConicResult {
    pub status: SolverStatus,
    pub x: Vec<f64>,
    /// The dual variables, one per row.
    pub z: Vec<f64>,
    pub obj: f64,
    pub obj_dual: f64,
    pub iterations: u32,
    /// clarabel's relative dual residual ‖Px + Aᵀz + q‖ / max(1, ‖q‖ + ‖x‖ + ‖z‖).
    pub r_dual: f64,
    /// ‖b‖ + ‖x‖ + ‖s‖ + ‖z‖ + ‖q‖: the scale the residuals are relative to.
    pub norms: f64,
}

/// clarabel with its duality-gap tolerance two orders tighter than the target relative gap
/// (within [1e-11, 1e-8]). Very tight tolerances sometimes end at AlmostSolved (reduced
/// accuracy); then the solve is repeated with tolerances 10× and 100× looser, and the
/// first full `Solved` is kept (the exchange loops' gap checks still verify the design).
pub(crate) fn run_clarabel(bt: &Built, rel_tol: f64) -> Result<ConicResult, String> {
    let gap_tol = (0.01 * rel_tol).clamp(1e-11, 1e-8);
    run_clarabel_with(bt, gap_tol, |g| (10.0 * g).clamp(1e-10, 1e-8), false)
}

/// [`run_clarabel`] with an explicit gap tolerance and the feasibility tolerance as a
/// function of it (the gap tolerance is loosened 10× per retry after an AlmostSolved).
pub(crate) fn run_clarabel_with(
    bt: &Built,
    gap_tol: f64,
    feas_tol: impl Fn(f64) -> f64,
    precise: bool,
) -> Result<ConicResult, String> {
    let mut gap_tol = gap_tol;
    let mut last = None;
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    for _ in 0..3 {
        let mut builder = DefaultSettingsBuilder::default();
        if precise {
            builder
                .iterative_refinement_max_iter(PRECISE_REFINE)
                .iterative_refinement_reltol(1e-16)
                .iterative_refinement_abstol(1e-16)
                .static_regularization_constant(PRECISE_REG);
        }
        let settings = builder
            .verbose(false)
            .tol_gap_abs(gap_tol)
            .tol_gap_rel(gap_tol)
            .tol_feas(feas_tol(gap_tol))
            .tol_ktratio(1e-10)
            .max_iter(100)
            .build()
            .map_err(|e| e.to_string())?;
        let mut solver = DefaultSolver::new(&bt.p, &bt.q, &bt.a, &bt.b, &bt.cones, settings)
            .map_err(|e| format!("clarabel setup: {e:?}"))?;
        solver.solve();
        let sol = &solver.solution;
        let res = ConicResult {
            status: sol.status,
            x: sol.x.clone(),
            z: sol.z.clone(),
            obj: sol.obj_val,
            obj_dual: sol.obj_val_dual,
            iterations: sol.iterations + last.as_ref().map_or(0, |r: &ConicResult| r.iterations),
            r_dual: sol.r_dual,
            norms: norm(&bt.b) + norm(&sol.x) + norm(&sol.s) + norm(&sol.z) + norm(&bt.q),
        };
        if res.status != SolverStatus::AlmostSolved {
            return Ok(res);
        }
        last = Some(res);
        gap_tol *= 10.0;
    }
    Ok(last.expect("three attempts"))
}

/// A rigorous lower bound of a conic program without quadratic term, min qᵀx s.t.
/// b − Ax ∈ K, from a dual iterate z, for the feasible points with |x_j| ≤ `xbound[j]`.
///
/// z is first put into the dual cone K* (negative parts of nonnegative-cone entries set to
/// 0, the head of a second-order cone raised to the norm of its tail; clarabel's iterates are
/// interior, so this only absorbs round-off). Then for every feasible x, with s = b − Ax ∈ K
/// and r = q + Aᵀz: qᵀx = −bᵀz + zᵀs + rᵀx ≥ −bᵀz − Σ_j |r_j| B_j, since zᵀs ≥ 0. The
/// round-off of the two sums (4ε times their absolute terms) is subtracted as well. Returns
/// (bound, Σ|r_j|B_j + round-off): the second is what the residual cost; an infinite B_j with
/// r_j ≠ 0 gives −∞.
pub(crate) fn dual_lower_bound(bt: &Built, z: &[f64], xbound: &[f64]) -> (f64, f64) {
    let mut z = z.to_vec();
    let mut at = 0;
    for cone in &bt.cones {
        match *cone {
            SupportedConeT::NonnegativeConeT(k) => {
                z[at..at + k].iter_mut().for_each(|v| *v = v.max(0.0));
                at += k;
            }
            SupportedConeT::SecondOrderConeT(k) => {
                let tail = z[at + 1..at + k].iter().map(|v| v * v).sum::<f64>().sqrt();
                z[at] = z[at].max(tail * (1.0 + 4.0 * f64::EPSILON));
                at += k;
            }
            SupportedConeT::ZeroConeT(k) => at += k,
            _ => unreachable!("the synth engines use zero, nonnegative and second-order cones"),
        }
    }
    let (mut d, mut d_abs) = (0.0, 0.0);
    for (b, z) in bt.b.iter().zip(&z) {
        d -= b * z;
        d_abs += (b * z).abs();
    }
    let a = &bt.a;
    let (mut pen, mut pen_abs) = (0.0, 0.0);
    for (j, &bj) in xbound.iter().enumerate().take(a.n) {
        let (mut r, mut r_abs) = (bt.q[j], bt.q[j].abs());
        for k in a.colptr[j]..a.colptr[j + 1] {
            let t = a.nzval[k] * z[a.rowval[k]];
            r += t;
            r_abs += t.abs();
        }
        let rr = r.abs() + 4.0 * f64::EPSILON * r_abs;
        if rr > 0.0 {
            pen += rr * bj;
            pen_abs += rr * bj;
        }
    }
    let pen = pen + 4.0 * f64::EPSILON * (d_abs + pen_abs);
    (d - pen, pen)
}
