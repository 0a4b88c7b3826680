//! Process loads on a linkage (issue 33): a press's pressing force, a cutting or pumping
//! force — a force on a point of a link, its magnitude a function of the crank angle.
//!
//! The load is reacted by the frame (the workpiece sits on the press's bed), so it is no part
//! of the shaking force or moment, which stay the inertial ones; it enters the input torque
//! (virtual work: the motor supplies T_L = −Σ F·X′ with X′ = dX/dθ of its point) and every
//! joint's load (Newton–Euler: the force and its moment join the link's wrench). Both are
//! independent of the links' inertial parameters: a constant term of the affine maps the
//! counterweight programs use.

use super::{Linkage, LinkageError, Pose};
use crate::geom::{cross, P2};
use std::f64::consts::TAU;

/// A force on a point of a link, of fixed direction, its magnitude piecewise linear in the
/// crank angle θ and 2π-periodic.
#[derive(Debug, Clone, PartialEq)]
pub struct ProcessLoad {
    /// The link it acts on.
    pub link: usize,
    /// Its point in the link's frame (m).
    pub at: P2,
    /// Its direction in the world (a unit vector).
    pub direction: P2,
    /// (θ in [0, 2π), magnitude in N), θ strictly increasing.
    pub table: Vec<(f64, f64)>,
}

impl ProcessLoad {
    /// The magnitude at θ: linear between the table's points, across 2π from the last back
    /// to the first.
    pub fn magnitude(&self, theta: f64) -> f64 {
        let t = theta.rem_euclid(TAU);
        let n = self.table.len();
        let k = self.table.partition_point(|p| p.0 <= t);
        let (a, b) = match k {
            0 => (self.table[n - 1], self.table[0]),
            k if k == n => (self.table[n - 1], self.table[0]),
            k => (self.table[k - 1], self.table[k]),
        };
        let span = (b.0 - a.0).rem_euclid(TAU);
        if span == 0.0 {
            return a.1;
        }
        let s = (t - a.0).rem_euclid(TAU) / span;
        a.1 + s * (b.1 - a.1)
    }

    /// The force at θ (N).
    pub fn force(&self, theta: f64) -> P2 {
        self.direction * self.magnitude(theta)
    }

    /// The table's crank angles: where the load has kinks.
    pub fn kinks(&self) -> impl Iterator<Item = f64> + '_ {
        self.table.iter().map(|p| p.0)
    }
}

impl Linkage {
    /// This linkage with the process loads `loads` (every link index must exist, every
    /// table hold at least one point with increasing finite angles in [0, 2π) and finite
    /// magnitudes).
    pub fn with_loads(mut self, loads: Vec<ProcessLoad>) -> Result<Linkage, LinkageError> {
        for (k, l) in loads.iter().enumerate() {
            let ordered = l.table.windows(2).all(|w| w[0].0 < w[1].0);
            let finite = l.table.iter().all(|p| p.0.is_finite() && p.1.is_finite());
            let in_turn = l.table.iter().all(|p| (0.0..TAU).contains(&p.0));
            let unit = (l.direction.norm() - 1.0).abs() < 1e-12;
            if l.link >= self.n_links() || l.table.is_empty() || !ordered || !finite {
                return Err(LinkageError::BadLoad { load: k });
            }
            if !in_turn || !unit || !(l.at.x.is_finite() && l.at.y.is_finite()) {
                return Err(LinkageError::BadLoad { load: k });
            }
        }
        self.loads = loads;
        Ok(self)
    }

    /// The process loads.
    pub fn loads(&self) -> &[ProcessLoad] {
        &self.loads
    }

    /// Each load's link, its point on the pose (X, X′, X″) and the force.
    fn load_points<'a>(
        &'a self,
        pose: &'a Pose,
    ) -> impl Iterator<Item = (usize, [P2; 3], P2)> + 'a {
        self.loads
            .iter()
            .map(move |l| (l.link, pose.links[l.link].point(l.at), l.force(pose.theta)))
    }

    /// The loads' torque on the crank, T_L = −Σ F·X′ (N·m): what the motor supplies for
    /// them (positive where the load resists the motion), and Σ |F|·|X′| (its scale, for
    /// round-off bounds).
    pub fn load_torque(&self, pose: &Pose) -> (f64, f64) {
        self.load_points(pose)
            .fold((0.0, 0.0), |(t, s), (_, x, f)| {
                (t - f.dot(&x[1]), s + f.norm() * x[1].norm())
            })
    }

    /// The loads' wrench on every link: (F_x, F_y, (X − P_i) × F) per link, 3 rows a link,
    /// for the joint-force equations.
    pub(super) fn load_wrench(&self, pose: &Pose) -> Vec<f64> {
        let mut w = vec![0.0; 3 * self.n_links()];
        for (i, x, f) in self.load_points(pose) {
            w[3 * i] += f.x;
            w[3 * i + 1] += f.y;
            w[3 * i + 2] += cross(x[0] - pose.links[i].p[0], f);
        }
        w
    }
}
