//! The design constraints of the minimax in the scaled variables as smooth functions
//! d(x̂) ≤ 0 (or = 0), with their gradients and Hessians: assembled with the cone program
//! (`assembly.rs`) and held to their multipliers by the Newton polish (`polish.rs`), so they
//! live apart from both.

use nalgebra::DMatrix;

/// One design constraint in the scaled variables as a smooth function: d(x̂) ≤ 0, or = 0.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Design {
    /// Σ a_j x̂_j − r (≤ 0, or = 0 when `eq`).
    Linear {
        /// (j, a_j).
        a: Vec<(usize, f64)>,
        /// r.
        r: f64,
        /// An equality.
        eq: bool,
    },
    /// |û| − k·m̂ − c ≤ 0: the centroid within r_max (k = r_max/ℓ, c = 0), or a tangent of
    /// a plate's cap bound (`plate.rs`).
    Radius {
        /// Index of m̂.
        m: usize,
        /// Index of û_x (û_y follows).
        u: usize,
        /// k.
        k: f64,
        /// c.
        c: f64,
    },
    /// |û|² − (Î − p·m̂ + q)·m̂ ≤ 0: a real body (J ≥ 0) at p = q = 0, or a tangent of a
    /// plate's disc condition (`plate.rs`).
    Body {
        /// Index of m̂.
        m: usize,
        /// Index of û_x.
        u: usize,
        /// Index of Î.
        i: usize,
        /// p.
        p: f64,
        /// q.
        q: f64,
    },
    /// m̂² − p·m̂ + q·Î ≤ 0: a plate's rim, I ≤ R²m − m²/(2πσ) (`plate.rs`).
    Rim {
        /// Index of m̂.
        m: usize,
        /// Index of Î.
        i: usize,
        /// p.
        p: f64,
        /// q.
        q: f64,
    },
}

impl Design {
    /// d(x̂).
    pub fn value(&self, x: &[f64]) -> f64 {
        match self {
            Design::Linear { a, r, .. } => a.iter().map(|&(j, c)| c * x[j]).sum::<f64>() - r,
            Design::Radius { m, u, k, c } => x[*u].hypot(x[u + 1]) - k * x[*m] - c,
            Design::Body { m, u, i, p, q } => {
                x[*u] * x[*u] + x[u + 1] * x[u + 1] - (x[*i] - p * x[*m] + q) * x[*m]
            }
            Design::Rim { m, i, p, q } => x[*m] * x[*m] - p * x[*m] + q * x[*i],
        }
    }
    /// An equality.
    pub fn is_eq(&self) -> bool {
        matches!(self, Design::Linear { eq: true, .. })
    }
    /// ∇d at x̂, written into `g` (length n, zeroed here).
    pub(super) fn grad(&self, x: &[f64], g: &mut [f64]) {
        g.iter_mut().for_each(|v| *v = 0.0);
        match self {
            Design::Linear { a, .. } => a.iter().for_each(|&(j, c)| g[j] += c),
            Design::Radius { m, u, k, .. } => {
                let r = x[*u].hypot(x[u + 1]);
                g[*m] = -k;
                if r > 0.0 {
                    g[*u] = x[*u] / r;
                    g[u + 1] = x[u + 1] / r;
                }
            }
            Design::Body { m, u, i, p, q } => {
                g[*u] = 2.0 * x[*u];
                g[u + 1] = 2.0 * x[u + 1];
                g[*i] = -x[*m];
                g[*m] = -x[*i] + 2.0 * p * x[*m] - q;
            }
            Design::Rim { m, i, p, q } => {
                g[*m] = 2.0 * x[*m] - p;
                g[*i] = *q;
            }
        }
    }
    /// Adds w·∇²d at x̂ to the block of `h` at (0, 0).
    pub(super) fn add_hessian(&self, x: &[f64], w: f64, h: &mut DMatrix<f64>) {
        match self {
            Design::Linear { .. } => {}
            Design::Radius { u, .. } => {
                let r = x[*u].hypot(x[u + 1]);
                if r > 0.0 {
                    let e = [x[*u] / r, x[u + 1] / r];
                    for a in 0..2 {
                        for b in 0..2 {
                            let id = if a == b { 1.0 } else { 0.0 };
                            h[(u + a, u + b)] += w * (id - e[a] * e[b]) / r;
                        }
                    }
                }
            }
            Design::Body { m, u, i, p, .. } => {
                h[(*u, *u)] += 2.0 * w;
                h[(u + 1, u + 1)] += 2.0 * w;
                h[(*m, *i)] -= w;
                h[(*i, *m)] -= w;
                h[(*m, *m)] += 2.0 * p * w;
            }
            Design::Rim { m, .. } => h[(*m, *m)] += 2.0 * w,
        }
    }
}
