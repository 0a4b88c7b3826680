//! A synthetic "linkage" for the minimax engine's tests and bench: links whose joint P(θ)
//! and angle ψ(θ) are short trigonometric series (no loop closure), each carrying its own
//! inertial parameters and one counterweight. Shared by `tests/minimax_engine.rs` and
//! `benches/minimax.rs` (included by path).
//!
//! A body (m, u = m p, I about P) on link j: ∫ r dm = m P + R(ψ) u, so per ω²
//! F = −(m P'' + R(ψ)(ψ'' J − ψ'²) u) and, from the angular momentum about O,
//! H = m P × P' + ψ' P × J R u + R u × P' + ψ' I,
//! M_O = −(m P × P'' + ψ'' P × J R u − ψ'² P × R u + R u × P'' + ψ'' I).
#![allow(dead_code)]

use cwsynth::synth::minimax::{var_i, var_m, var_u, AffineValue};

/// One link's motion.
#[derive(Debug, Clone, Copy)]
pub struct Link {
    /// P(θ) = c + a (cos(θ + α), sin(θ + α)) + e (cos(2θ + β), sin(2θ + β)).
    pub c: [f64; 2],
    pub a: f64,
    pub alpha: f64,
    pub e: f64,
    pub beta: f64,
    /// ψ(θ) = γ + k θ + h sin(θ + δ).
    pub gamma: f64,
    pub k: f64,
    pub h: f64,
    pub delta: f64,
    /// The link's own (m, u_x, u_y, I about P).
    pub own: [f64; 4],
}

/// Rows (F_x, F_y, M) of one body on `link` at θ, per ω²: coefficients of (m, u_x, u_y, I).
pub fn body_rows(l: &Link, th: f64) -> [[f64; 4]; 3] {
    let (s1, c1) = (th + l.alpha).sin_cos();
    let (s2, c2) = (2.0 * th + l.beta).sin_cos();
    let p = [l.c[0] + l.a * c1 + l.e * c2, l.c[1] + l.a * s1 + l.e * s2];
    let p2 = [-l.a * c1 - 4.0 * l.e * c2, -l.a * s1 - 4.0 * l.e * s2];
    let psi = l.gamma + l.k * th + l.h * (th + l.delta).sin();
    let d1 = l.k + l.h * (th + l.delta).cos();
    let d2 = -l.h * (th + l.delta).sin();
    let (sp, cp) = psi.sin_cos();
    let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
    let mut rows = [[0.0; 4]; 3];
    rows[0][0] = -p2[0];
    rows[1][0] = -p2[1];
    rows[2][0] = -cross(p, p2);
    rows[2][3] = -d2;
    for (col, w) in [(1, [cp, sp]), (2, [-sp, cp])] {
        // R(ψ)(ψ'' J − ψ'²) e = ψ'' J w − ψ'² w, J w = (−w_y, w_x).
        let jw = [-w[1], w[0]];
        let acc = [d2 * jw[0] - d1 * d1 * w[0], d2 * jw[1] - d1 * d1 * w[1]];
        rows[0][col] = -acc[0];
        rows[1][col] = -acc[1];
        rows[2][col] = -(d2 * cross(p, jw) - d1 * d1 * cross(p, w) + cross(w, p2));
    }
    rows
}

/// A mechanism of `links`, one counterweight per link, at speed ω.
pub struct Synthetic {
    pub links: Vec<Link>,
    pub omega: f64,
}

impl Synthetic {
    /// Deterministic pseudo-random links (an LCG from `seed`): sizes ~0.1 m, masses ~1 kg.
    pub fn random(k: usize, seed: u64, omega: f64) -> Self {
        let mut st = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut r = move || {
            st = st
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((st >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let links = (0..k)
            .map(|j| {
                let m = 1.0 + 0.5 * r();
                let cx = 0.02 * r();
                let cy = 0.02 * r();
                Link {
                    c: [0.1 * r(), 0.1 * r()],
                    a: 0.05 * (1.0 + 0.5 * r()) * if j == 0 { 1.0 } else { 0.5 },
                    alpha: 3.0 * r(),
                    e: 0.01 * r(),
                    beta: 3.0 * r(),
                    gamma: 3.0 * r(),
                    k: if j == 0 { 1.0 } else { 0.0 },
                    h: if j == 0 { 0.0 } else { 0.5 * (1.0 + 0.5 * r()) },
                    delta: 3.0 * r(),
                    own: [m, m * cx, m * cy, m * (0.002 + cx * cx + cy * cy)],
                }
            })
            .collect();
        Synthetic { links, omega }
    }

    /// Field `which` (0: force F, 2 rows; 1: moment M_O, 1 row) at θ, N or N·m.
    pub fn eval(&self, which: usize, th: f64, out: &mut AffineValue) {
        let w2 = self.omega * self.omega;
        for (j, l) in self.links.iter().enumerate() {
            let rows = body_rows(l, th);
            let idx = [var_m(j), var_u(j), var_u(j) + 1, var_i(j)];
            let sel: &[usize] = if which == 0 { &[0, 1] } else { &[2] };
            for (r, &src) in sel.iter().enumerate() {
                let row = out.row_mut(r);
                for c in 0..4 {
                    row[idx[c]] = w2 * rows[src][c];
                }
                out.b[r] += w2 * (0..4).map(|c| rows[src][c] * l.own[c]).sum::<f64>();
            }
        }
    }
}
