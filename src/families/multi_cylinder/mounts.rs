//! The frame the cylinders shake, on elastic mounts (`shared/domain/multi-cylinder.md`,
//! "Mounts"): a rigid body of mass M and principal inertias (I_x, I_y, I_z) about its centre of
//! mass G (axes along the shaft frame's), on linear springs and viscous dampers, each mount
//! with its stiffness and damping along x, y and z at its point. Six coordinates
//! q = (u, θ): the displacement of G and the small rotation; a frame point p moves by
//! δ = u + θ × (p − G) = T(p) q with T = [I | −[p − G]×].
//!
//! M q̈ + C q̇ + K q = Q(t), K = Σ T_kᵀ diag(k_k) T_k, C likewise, Q = [F; (s − G) × F + M]
//! for the shaking force F acting at the shaft point s = (0, 0, z₀) and the moment M about it
//! (the couple about x and y, the roll about the shaft).
//! At one order n the steady state is the linear solve q̂ = (K − Ω²M + iΩC)⁻¹ Q̂ at Ω = nω, and a
//! mount transmits f̂_k = (diag(k_k) + iΩ diag(c_k)) T_k q̂ to the ground: linear in Q̂, so in the
//! design's unbalances. A 6×6 complex solve per order: nalgebra's LU.

use nalgebra::{Complex, Matrix3, Matrix6, SMatrix, Vector3, Vector6};

/// One mount: where it holds the frame and its spring and damper along x, y, z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Its point (m, shaft frame).
    pub at: [f64; 3],
    /// Stiffness along x, y, z (N/m).
    pub stiffness: [f64; 3],
    /// Viscous damping along x, y, z (N·s/m).
    pub damping: [f64; 3],
}

/// The frame: a rigid body on its mounts.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// M (kg): the frame with everything fixed to it (the cylinders' housings).
    pub mass: f64,
    /// Principal inertias about G along x, y, z (kg·m²).
    pub inertia: [f64; 3],
    /// G (m, shaft frame).
    pub centroid: [f64; 3],
    /// The mounts.
    pub mounts: Vec<Mount>,
}

/// [r]×, the matrix of v ↦ r × v.
fn skew(r: Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

impl Frame {
    /// T(p): the displacement of the frame point p per q (3 × 6).
    pub fn t(&self, p: [f64; 3]) -> SMatrix<f64, 3, 6> {
        let r = Vector3::from(p) - Vector3::from(self.centroid);
        let mut t = SMatrix::<f64, 3, 6>::zeros();
        t.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        t.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(r)));
        t
    }

    /// Σ T_kᵀ diag(d_k) T_k for each mount's `d` (its stiffness or damping).
    fn assemble(&self, d: impl Fn(&Mount) -> [f64; 3]) -> Matrix6<f64> {
        self.mounts.iter().fold(Matrix6::zeros(), |acc, m| {
            let t = self.t(m.at);
            acc + t.transpose() * Matrix3::from_diagonal(&Vector3::from(d(m))) * t
        })
    }

    /// K.
    pub fn stiffness(&self) -> Matrix6<f64> {
        self.assemble(|m| m.stiffness)
    }

    /// C.
    pub fn damping(&self) -> Matrix6<f64> {
        self.assemble(|m| m.damping)
    }

    /// The mass matrix diag(M, M, M, I_x, I_y, I_z).
    pub fn mass_matrix(&self) -> Matrix6<f64> {
        let [a, b, c] = self.inertia;
        Matrix6::from_diagonal(&Vector6::new(self.mass, self.mass, self.mass, a, b, c))
    }

    /// The dynamic stiffness K − Ω²M + iΩC at Ω (rad/s).
    pub fn dynamic(&self, w: f64) -> Matrix6<Complex<f64>> {
        let (k, m, c) = (self.stiffness(), self.mass_matrix(), self.damping());
        Matrix6::from_fn(|i, j| Complex::new(k[(i, j)] - w * w * m[(i, j)], w * c[(i, j)]))
    }

    /// Q from the force F (N) at the shaft point (0, 0, z₀) and the moment M (N·m) about it —
    /// the couple (M_x, M_y) and the roll M_z about the shaft —, as complex amplitudes of one
    /// order (or real values at one instant).
    pub fn load<T: nalgebra::ComplexField + Copy>(
        &self,
        z0: f64,
        f: [T; 2],
        m: [T; 3],
    ) -> Vector6<T> {
        let [gx, gy, gz] = self.centroid;
        let s = [-gx, -gy, z0 - gz].map(|v| T::from_real(nalgebra::convert(v)));
        // (s − G) × F with F = (f_x, f_y, 0).
        let arm = [-s[2] * f[1], s[2] * f[0], s[0] * f[1] - s[1] * f[0]];
        Vector6::new(
            f[0],
            f[1],
            T::zero(),
            arm[0] + m[0],
            arm[1] + m[1],
            arm[2] + m[2],
        )
    }

    /// The transfer of one order: from (F̂_x, F̂_y, M̂_x, M̂_y, M̂_z) to each mount's transmitted
    /// force (x, y, z), at Ω; `None` where K − Ω²M + iΩC is singular (an undamped resonance).
    pub fn transfer(&self, z0: f64, w: f64) -> Option<Vec<SMatrix<Complex<f64>, 3, 5>>> {
        let lu = self.dynamic(w).lu();
        let one = Complex::new(1.0, 0.0);
        let zero = Complex::new(0.0, 0.0);
        let unit = |k: usize| {
            let mut f = [zero; 2];
            let mut m = [zero; 3];
            if k < 2 {
                f[k] = one;
            } else {
                m[k - 2] = one;
            }
            lu.solve(&self.load(z0, f, m))
        };
        let q: Vec<Vector6<Complex<f64>>> = (0..5).map(unit).collect::<Option<_>>()?;
        Some(
            self.mounts
                .iter()
                .map(|m| {
                    let t = self.t(m.at).map(|v| Complex::new(v, 0.0));
                    let g = Matrix3::from_fn(|i, j| {
                        if i == j {
                            Complex::new(m.stiffness[i], w * m.damping[i])
                        } else {
                            zero
                        }
                    });
                    SMatrix::<Complex<f64>, 3, 5>::from_fn(|i, j| (g * t * q[j])[i])
                })
                .collect(),
        )
    }

    /// The undamped natural frequencies (rad/s), ascending: √ of the eigenvalues of
    /// M^−½ K M^−½ (symmetric; a zero for a direction no mount holds).
    pub fn natural_frequencies(&self) -> Vec<f64> {
        let m = self.mass_matrix();
        let s = Matrix6::from_diagonal(&m.diagonal().map(|v| 1.0 / v.sqrt()));
        let a = s * self.stiffness() * s;
        let mut w: Vec<f64> = a
            .symmetric_eigenvalues()
            .iter()
            .map(|v| v.max(0.0).sqrt())
            .collect();
        w.sort_by(f64::total_cmp);
        w
    }
}

/// The complex amplitudes (x, y) of a planar vector's order n from its forward and backward
/// coefficients: v_x + i v_y = c₊e^{inφ} + c₋e^{−inφ} gives v_x = Re[(c₊ + c̄₋)e^{inφ}] and
/// v_y = Re[(−ic₊ + ic̄₋)e^{inφ}].
pub fn components(fwd: Complex<f64>, bwd: Complex<f64>) -> [Complex<f64>; 2] {
    let i = Complex::new(0.0, 1.0);
    [fwd + bwd.conj(), -i * fwd + i * bwd.conj()]
}
