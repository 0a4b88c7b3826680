//! A small dense convex QP, min ½xᵀHx + cᵀx subject to Ax ≤ b, solved by the primal
//! active-set method from a feasible start: the SQP's subproblems ([`super::sqp`]), with
//! about ten variables and twenty rows, in tens of thousands of instructions where an
//! interior-point solve costs close to a million (its set-up, equilibration and sparse
//! factorisations are built for large problems).
//!
//! The method is Nocedal & Wright, *Numerical Optimization*, 2nd ed., Springer 2006,
//! Algorithm 16.3: each iteration solves the equality-constrained QP on the working set W
//! through its KKT system
//!
//! ```text
//! [ H   A_Wᵀ ] [ p ]   [ −(Hx + c) ]
//! [ A_W  0   ] [ λ ] = [     0     ]
//! ```
//!
//! then either steps along p to the first blocking row (which joins W) or, at the minimiser
//! on W, drops the row of the most negative multiplier. H may be only semidefinite (the SQP's
//! level variables and slacks are linear): the method needs the reduced Hessian on the null
//! space of the starting W to be positive definite, which a start with every linear variable
//! pinned by a row gives; a blocking row is never a combination of W's (it has aᵀp > 0 where
//! W's rows have aᵀp = 0), so W keeps full row rank.
//!
//! It is hand-written because no crate fits: `quadprog` (Goldfarb–Idnani) is GPL-2.0, which
//! this MIT/Apache crate cannot link, and wants H strictly positive definite; `osqp` wraps C
//! and is a first-order method (ADMM) with loose tolerances; clarabel is what it replaces
//! where the problem is this small. Every answer is checked — primal feasibility,
//! multipliers ≥ 0, the stationarity residual — and `None` (singular KKT system, iteration
//! limit, a failed check) tells the caller to fall back to clarabel.

/// A dense QP: `n` variables, `h` (n×n, row-major, symmetric positive semidefinite), `c`,
/// and the rows `a` (m×n, row-major) of A x ≤ b.
#[derive(Debug, Clone, Copy)]
pub struct DenseQp<'a> {
    /// Number of variables.
    pub n: usize,
    /// H, row-major.
    pub h: &'a [f64],
    /// The linear term.
    pub c: &'a [f64],
    /// A's rows, row-major.
    pub a: &'a [f64],
    /// The right-hand sides.
    pub b: &'a [f64],
}

/// The optimum of a [`DenseQp`] and its certificate.
#[derive(Debug, Clone)]
pub struct QpSolution {
    /// The minimiser.
    pub x: Vec<f64>,
    /// One multiplier per row (0 off the final working set), ≥ 0: Hx + c + Aᵀλ = 0.
    pub lambda: Vec<f64>,
    /// ½xᵀHx + cᵀx.
    pub objective: f64,
}

impl DenseQp<'_> {
    fn m(&self) -> usize {
        self.b.len()
    }

    fn row(&self, i: usize) -> &[f64] {
        &self.a[i * self.n..(i + 1) * self.n]
    }

    /// Hx + c.
    fn gradient(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|i| dot(&self.h[i * self.n..(i + 1) * self.n], x) + self.c[i])
            .collect()
    }

    /// The step p and the multipliers λ of the equality-constrained QP on W at x (module
    /// doc); `None` when its KKT matrix is singular to working precision.
    fn eqp(&self, x: &[f64], w: &[usize]) -> Option<(Vec<f64>, Vec<f64>)> {
        let (n, k) = (self.n, self.n + w.len());
        let mut kkt = vec![0.0; k * k];
        for i in 0..n {
            kkt[i * k..i * k + n].copy_from_slice(&self.h[i * n..(i + 1) * n]);
        }
        for (r, &row) in w.iter().enumerate() {
            for (j, &v) in self.row(row).iter().enumerate() {
                kkt[(n + r) * k + j] = v;
                kkt[j * k + n + r] = v;
            }
        }
        let mut rhs: Vec<f64> = self.gradient(x).iter().map(|g| -g).collect();
        rhs.resize(k, 0.0);
        let sol = solve_dense(kkt, rhs)?;
        Some((sol[..n].to_vec(), sol[n..].to_vec()))
    }
}

/// a · b.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Minimise the QP from a feasible `x0` with the working set `w0` (rows active at x0,
/// linearly independent, pinning every direction of zero curvature: module doc) by the
/// primal active-set method; `None` when a KKT system is singular, the iteration limit
/// is met or the answer fails its check (the caller then uses an interior-point solver).
pub fn active_set(
    qp: &DenseQp,
    x0: Vec<f64>,
    w0: Vec<usize>,
    max_iter: usize,
) -> Option<QpSolution> {
    let mut x = x0;
    let mut w = w0;
    let mut at_minimum = false;
    for _ in 0..max_iter {
        let (p, lam) = qp.eqp(&x, &w)?;
        let pn = p.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let xn = x.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        if at_minimum || pn <= 1e-15 * xn {
            let scale = lam.iter().fold(1e-300f64, |a, v| a.max(v.abs()));
            let most = (0..lam.len()).min_by(|&i, &j| lam[i].total_cmp(&lam[j]));
            match most {
                Some(j) if lam[j] < -1e-12 * scale => {
                    w.remove(j);
                    at_minimum = false;
                }
                _ => return certified(qp, x, &w, &lam),
            }
            continue;
        }
        let (alpha, block) = ratio_test(qp, &x, &p, &w);
        for (xi, pi) in x.iter_mut().zip(&p) {
            *xi += alpha * pi;
        }
        match block {
            Some(i) => {
                w.push(i);
                at_minimum = false;
            }
            None => at_minimum = true,
        }
    }
    None
}

/// The longest step α ≤ 1 along p that keeps every row off W feasible, and the row that
/// blocks it (the lowest index among ties).
fn ratio_test(qp: &DenseQp, x: &[f64], p: &[f64], w: &[usize]) -> (f64, Option<usize>) {
    let mut alpha = 1.0;
    let mut block = None;
    for i in (0..qp.m()).filter(|i| !w.contains(i)) {
        let ap = dot(qp.row(i), p);
        // A row that p leaves by rounding only (a repeat of one in W: aᵀp ~ ε|a||p|) does
        // not block: adding it would make W's rows dependent.
        let noise = 1e-13
            * qp.row(i)
                .iter()
                .zip(p)
                .map(|(a, v)| (a * v).abs())
                .sum::<f64>();
        if ap <= noise {
            continue;
        }
        let room = (qp.b[i] - dot(qp.row(i), x)).max(0.0);
        if room < alpha * ap {
            alpha = room / ap;
            block = Some(i);
        }
    }
    (alpha, block)
}

/// The solution at x with W's multipliers, if it passes its check: every row met to 1e-12
/// of |b| + |a|₁|x|∞ and λ ≥ 0, and the stationarity residual Hx + c + Aᵀλ within 1e-10 of the
/// gradient's scale.
fn certified(qp: &DenseQp, x: Vec<f64>, w: &[usize], lam_w: &[f64]) -> Option<QpSolution> {
    let mut lambda = vec![0.0; qp.m()];
    for (&row, &l) in w.iter().zip(lam_w) {
        lambda[row] = l.max(0.0);
    }
    // A row's rounding is relative to |b| and |a|₁|x|∞ (a slack computed as a difference
    // of larger numbers may end a few ε below its bound 0).
    let xn = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let feasible = (0..qp.m()).all(|i| {
        let size = qp.b[i].abs() + qp.row(i).iter().map(|a| a.abs()).sum::<f64>() * xn;
        dot(qp.row(i), &x) - qp.b[i] <= 1e-12 * size
    });
    let g = qp.gradient(&x);
    let gscale = g.iter().chain(qp.c).fold(1e-300f64, |a, v| a.max(v.abs()));
    let stationary = (0..qp.n).all(|j| {
        let r = g[j]
            + (0..qp.m())
                .map(|i| qp.a[i * qp.n + j] * lambda[i])
                .sum::<f64>();
        r.abs() <= 1e-10 * gscale
    });
    if !(feasible && stationary) {
        return None;
    }
    let hx: Vec<f64> = g.iter().zip(qp.c).map(|(gi, ci)| gi - ci).collect();
    let objective = 0.5 * dot(&x, &hx) + dot(qp.c, &x);
    Some(QpSolution {
        x,
        lambda,
        objective,
    })
}

/// Solves the small dense system M w = b (M k×k, row-major) by Gaussian elimination with
/// partial pivoting; `None` when M is singular to working precision (a pivot below 1e-12 of
/// M's largest entry).
pub fn solve_dense(mut m: Vec<f64>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let k = b.len();
    let scale = m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut nz = Vec::with_capacity(k);
    for col in 0..k {
        let piv =
            (col..k).max_by(|&i, &j| m[i * k + col].abs().total_cmp(&m[j * k + col].abs()))?;
        if piv != col {
            for c in 0..k {
                m.swap(col * k + c, piv * k + c);
            }
            b.swap(col, piv);
        }
        let d = m[col * k + col];
        if !(d.abs() > 1e-12 * scale) {
            return None;
        }
        // A KKT matrix is mostly zeros: only the pivot row's nonzero columns are updated.
        nz.clear();
        nz.extend((col..k).filter(|&c| m[col * k + c] != 0.0));
        for r in col + 1..k {
            let f = m[r * k + col] / d;
            if f == 0.0 {
                continue;
            }
            for &c in &nz {
                m[r * k + c] -= f * m[col * k + c];
            }
            b[r] -= f * b[col];
        }
    }
    let mut w = vec![0.0; k];
    for r in (0..k).rev() {
        let s: f64 = (r + 1..k).map(|c| m[r * k + c] * w[c]).sum();
        w[r] = (b[r] - s) / m[r * k + r];
    }
    w.iter().all(|v| v.is_finite()).then_some(w)
}
