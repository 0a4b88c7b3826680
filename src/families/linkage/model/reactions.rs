//! The joint reactions of a linkage: the joints in the order of the unknowns, the
//! equilibrium system of every link (d'Alembert: the inertial wrench, gravity, the process
//! loads and the drive torque balanced by the reactions), and its solution as a map affine in
//! the links' inertial parameters.

use super::{inertial_wrench_at, Dyad, Linkage, LinkageError, Params, Point, Pose};
use crate::geom::{cross, perp, P2};
use nalgebra::{DMatrix, DVector};

/// One of the two bodies a joint connects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Body {
    /// The frame.
    Frame,
    /// Moving link i.
    Link(usize),
}

/// What a joint transmits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// A pin: a force (two components).
    Revolute,
    /// A slide: a force normal to the slide and a couple.
    Prismatic,
}

/// A joint between `first` and link `second`.
///
/// Revolute: at the point `at` of `second` (its frame); the unknowns are the force R that
/// `first` exerts on `second` (world x, y). Prismatic: the slide runs along `second`'s x axis;
/// the unknowns are N and C, the force N·J e_second that `first` exerts on `second` at
/// `second`'s reference joint, and the couple C. `first` receives the opposite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joint {
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// The body that exerts the joint's unknown force on `second`.
    pub first: Body,
    /// The link that receives it.
    pub second: usize,
    /// The joint's point in `second`'s frame (revolute; the origin for prismatic).
    pub at: P2,
}

/// Joint reactions at one angle, for given parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Reactions {
    /// θ (rad).
    pub theta: f64,
    /// Per joint ([`Linkage::joints`]): revolute (R_x, R_y) (N); prismatic (N (N), C (N·m)).
    pub loads: Vec<[f64; 2]>,
    /// The input torque on the crank (N·m), from the equilibrium of the links.
    pub torque: f64,
}

/// The joint reactions as an affine map of the links' parameters: the unknown vector
/// x = (joint loads as in [`Reactions::loads`], flattened, then T) is x = Σ_i B_i p_i.
#[derive(Debug, Clone, PartialEq)]
pub struct ReactionMap {
    /// θ (rad).
    pub theta: f64,
    /// x of the bare linkage.
    pub base: DVector<f64>,
    /// B_i (unknowns × 4) per link.
    pub blocks: Vec<DMatrix<f64>>,
}

impl Linkage {
    /// The joints, in the order of the unknowns of [`Linkage::reactions`]: the crank's pivot
    /// (frame → crank), then per dyad — RRR: P → a, a → b at B, Q → b; RRP: P → a, a → b at B,
    /// frame → slider (prismatic); RPR: P → a, a → b (prismatic), Q → b. "P → a" means the
    /// body that carries P (frame or a link) acts on link a.
    pub fn joints(&self) -> Vec<Joint> {
        let owner = |pt: &Point| match *pt {
            Point::Frame(_) => Body::Frame,
            Point::On { link, .. } => Body::Link(link),
        };
        let rev = |first, second, at| Joint {
            kind: JointKind::Revolute,
            first,
            second,
            at,
        };
        let pri = |first, second| Joint {
            kind: JointKind::Prismatic,
            first,
            second,
            at: P2::zeros(),
        };
        let o = P2::zeros();
        let mut out = vec![rev(Body::Frame, 0, o)];
        for (k, d) in self.dyads.iter().enumerate() {
            let (a, b) = Self::dyad_links(k);
            match d {
                Dyad::Rrr { p, q, l2, .. } => {
                    out.push(rev(owner(p), a, o));
                    out.push(rev(Body::Link(a), b, P2::new(*l2, 0.0)));
                    out.push(rev(owner(q), b, o));
                }
                Dyad::Rrp { p, .. } => {
                    out.push(rev(owner(p), a, o));
                    out.push(rev(Body::Link(a), b, o));
                    out.push(pri(Body::Frame, b));
                }
                Dyad::Rpr { p, q, .. } => {
                    out.push(rev(owner(p), a, o));
                    out.push(pri(Body::Link(a), b));
                    out.push(rev(owner(q), b, o));
                }
            }
        }
        out
    }

    /// The joint-force equations at a pose: K x + W(p) = 0 with x the unknowns (joint loads,
    /// then T), three rows per link (force x, y; moment about P_i), W the d'Alembert and
    /// gravity wrench of each link. Returns K and, per link, the 3×4 map of p_i into its
    /// wrench (F = m g − ω² (m P'' + E2 u), M_P = (R u) × (g − ω² P'') − ω² I_P ψ'' at
    /// constant speed; at real speed every ω²(·)'' is ω²(·)'' + α(·)', [`inertial_wrench_at`]).
    fn reaction_system(
        &self,
        pose: &Pose,
        omega: f64,
        alpha: f64,
    ) -> (DMatrix<f64>, Vec<nalgebra::Matrix3x4<f64>>) {
        let n = self.n_links();
        let joints = self.joints();
        let nu = 2 * joints.len() + 1;
        let mut k = DMatrix::<f64>::zeros(3 * n, nu);
        for (j, jt) in joints.iter().enumerate() {
            let s = &pose.links[jt.second];
            match jt.kind {
                JointKind::Revolute => {
                    let x = s.point(jt.at)[0];
                    // R on second, −R on first; moment about each body's P.
                    let mut put = |body: usize, sign: f64| {
                        let d = x - pose.links[body].p[0];
                        k[(3 * body, 2 * j)] += sign;
                        k[(3 * body + 1, 2 * j + 1)] += sign;
                        k[(3 * body + 2, 2 * j)] += -sign * d.y;
                        k[(3 * body + 2, 2 * j + 1)] += sign * d.x;
                    };
                    put(jt.second, 1.0);
                    if let Body::Link(f) = jt.first {
                        put(f, -1.0);
                    }
                }
                JointKind::Prismatic => {
                    let nrm = perp(s.e);
                    let x = s.p[0];
                    let mut put = |body: usize, sign: f64| {
                        let d = x - pose.links[body].p[0];
                        k[(3 * body, 2 * j)] += sign * nrm.x;
                        k[(3 * body + 1, 2 * j)] += sign * nrm.y;
                        k[(3 * body + 2, 2 * j)] += sign * cross(d, nrm);
                        k[(3 * body + 2, 2 * j + 1)] += sign;
                    };
                    put(jt.second, 1.0);
                    if let Body::Link(f) = jt.first {
                        put(f, -1.0);
                    }
                }
            }
        }
        k[(2, nu - 1)] = 1.0;
        let w2 = omega * omega;
        let g = self.gravity;
        let wrenches = pose
            .links
            .iter()
            .map(|ls| {
                let (fm, mp) = inertial_wrench_at(ls, w2, alpha);
                let rg = ls.rot().transpose() * perp(g);
                let mut w = nalgebra::Matrix3x4::<f64>::zeros();
                w.fixed_view_mut::<2, 4>(0, 0).copy_from(&fm);
                w.fixed_view_mut::<1, 4>(2, 0).copy_from(&mp);
                w[(0, 0)] += g.x;
                w[(1, 0)] += g.y;
                // (R u) × g = −(Rᵀ J g)·u.
                w[(2, 1)] -= rg.x;
                w[(2, 2)] -= rg.y;
                w
            })
            .collect();
        (k, wrenches)
    }

    /// Newton–Euler joint reactions and input torque at a pose for the parameters `params`
    /// (one per link): each link's joint forces balance its d'Alembert force −m r̈_G, couple
    /// −J ψ̈ and weight m g; the motor torque T acts on the crank. Independent of the
    /// energy form of [`Blocks::torque`]. Singular only at a toggle; near one the loads grow
    /// like κ and their round-off like the pose's ([`BalanceMap::rho`]) times κ.
    pub fn reactions(&self, pose: &Pose, params: &[Params]) -> Result<Reactions, LinkageError> {
        self.reactions_at(pose, params, self.omega, 0.0)
    }

    /// [`Linkage::reactions`] with the crank at speed `omega` (rad/s) and angular acceleration
    /// `alpha` (rad/s²), as in a real machine's steady state: T is then the torque the crank's
    /// shaft delivers to the linkage.
    pub fn reactions_at(
        &self,
        pose: &Pose,
        params: &[Params],
        omega: f64,
        alpha: f64,
    ) -> Result<Reactions, LinkageError> {
        let (k, w) = self.reaction_system(pose, omega, alpha);
        // The process loads' wrench, then the inertial and weight wrench of the parameters.
        let mut rhs = -DVector::from_vec(self.load_wrench(pose));
        for (i, (wi, p)) in w.iter().zip(params).enumerate() {
            let v = wi * p;
            for r in 0..3 {
                rhs[3 * i + r] -= v[r];
            }
        }
        let x = k
            .lu()
            .solve(&rhs)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or(LinkageError::SingularReactions { theta: pose.theta })?;
        let nj = (x.len() - 1) / 2;
        Ok(Reactions {
            theta: pose.theta,
            loads: (0..nj).map(|j| [x[2 * j], x[2 * j + 1]]).collect(),
            torque: x[x.len() - 1],
        })
    }

    /// [`Linkage::reactions`] with a bound on the round-off of every load and of T: the
    /// computed x = K⁻¹b (K the joint-force matrix, b = −Σ W_i p_i) differs from the exact one
    /// by at most ‖δx‖ ≤ (1/σ_min(K))·(ρ Σ_i ‖W_i‖_F ‖p_i‖ + (ρ + 8 n ε) ‖K‖₂ ‖x‖), the
    /// first-order perturbation bound of a linear system with the wrench and the lever arms
    /// known to ρ ([`BalanceMap::rho`], which covers the pose's accelerations near a toggle)
    /// and a backward-stable LU of size n. It grows like the conditioning of K, which is
    /// singular only at a toggle.
    pub fn reactions_with_error(
        &self,
        pose: &Pose,
        params: &[Params],
    ) -> Result<(Reactions, f64), LinkageError> {
        self.reactions_with_error_at(pose, params, self.omega, 0.0)
    }

    /// [`Linkage::reactions_with_error`] at speed `omega` and acceleration `alpha`
    /// ([`Linkage::reactions_at`]).
    pub fn reactions_with_error_at(
        &self,
        pose: &Pose,
        params: &[Params],
        omega: f64,
        alpha: f64,
    ) -> Result<(Reactions, f64), LinkageError> {
        let r = self.reactions_at(pose, params, omega, alpha)?;
        let (k, w) = self.reaction_system(pose, omega, alpha);
        let sv = k.singular_values();
        let (smin, smax) = (sv.min(), sv.max());
        if !(smin > 0.0) {
            return Err(LinkageError::SingularReactions { theta: pose.theta });
        }
        let rho = 64.0 * f64::EPSILON * pose.amp();
        let wp: f64 = w
            .iter()
            .zip(params)
            .map(|(wi, p)| wi.norm() * p.norm())
            .sum::<f64>()
            + DVector::from_vec(self.load_wrench(pose)).norm();
        let x = r
            .loads
            .iter()
            .map(|l| l[0] * l[0] + l[1] * l[1])
            .sum::<f64>()
            + r.torque * r.torque;
        let n = k.ncols() as f64;
        let bound = (rho * wp + (rho + 8.0 * n * f64::EPSILON) * smax * x.sqrt()) / smin;
        Ok((r, bound))
    }

    /// The joint reactions as a linear map of the parameters ([`ReactionMap`]): one LU of the
    /// joint-force matrix, solved for the 4 unit parameters of every link.
    pub fn reaction_map(&self, pose: &Pose) -> Result<ReactionMap, LinkageError> {
        let (k, w) = self.reaction_system(pose, self.omega, 0.0);
        let rows = k.nrows();
        let lu = k.lu();
        let singular = LinkageError::SingularReactions { theta: pose.theta };
        let mut blocks = Vec::with_capacity(w.len());
        for (i, wi) in w.iter().enumerate() {
            let mut rhs = DMatrix::<f64>::zeros(rows, 4);
            for r in 0..3 {
                for c in 0..4 {
                    rhs[(3 * i + r, c)] = -wi[(r, c)];
                }
            }
            let b = lu.solve(&rhs).ok_or(singular.clone())?;
            if !b.iter().all(|v| v.is_finite()) {
                return Err(singular.clone());
            }
            blocks.push(b);
        }
        // The process loads' part: K x = −w_L.
        let mut base = lu
            .solve(&-DVector::from_vec(self.load_wrench(pose)))
            .filter(|b| b.iter().all(|v| v.is_finite()))
            .ok_or(singular)?;
        for (b, p) in blocks.iter().zip(self.params()) {
            base += b * p;
        }
        Ok(ReactionMap {
            theta: pose.theta,
            base,
            blocks,
        })
    }
}
