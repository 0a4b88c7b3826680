//! A counterweight that is a flat plate of areal density σ (kg/m², density × thickness) cut
//! from anywhere within its envelope disc of radius R about the joint: the convex necessary
//! conditions on its (m, u, I), as cones of the round's program and as smooth constraints
//! of the polish, with the cutting planes that make them tight where the design lands.
//!
//! With A = m/σ its area and k = 2πσ:
//! * **area**: m ≤ σπR² (the caller's m_max);
//! * **first moment**: |u| ≤ σ S(m/σ), S(A) the first moment of the circular segment (cap)
//!   of area A, the most any region of that area has ([`crate::geom::plate::cap`]). S is
//!   concave (S′ = h, the chord's distance from the centre, falls as A grows), so each
//!   tangent |u| ≤ σ(S₀ − h₀A₀) + h₀ m is a second-order cone and the set of them an outer
//!   approximation;
//! * **rim**: I ≤ R² m − m²/k, the annulus at the rim having the largest polar moment of any
//!   region of its area: one rotated cone m² ≤ k (R² m − I), exact;
//! * **disc**: I ≥ |u|²/m + m²/k, a body's centroidal polar moment being at least the disc's
//!   of its area (I_c ≥ m A/(2π)); m²/k is convex, so each tangent
//!   I − (2m₀m − m₀²)/k ≥ |u|²/m is a rotated cone and the set of them an outer
//!   approximation. This is the condition that forbids slivers.
//!
//! Every tangent set is an outer approximation of the exact conditions, which are themselves
//! necessary: a program over them is a relaxation, and its bound a rigorous lower bound of
//! the plate's optimum. The tangents are seeded at a few masses, and after every round a
//! tangent is added at the round's mass where its design breaks the exact condition
//! (Kelley's cutting planes, J. SIAM 8 (1960) 703): the next round cannot land there again,
//! so the rounds go on until no condition is broken by more than [`CUT_TOL`] of its scale.
//! The design returned is then projected onto the exact conditions (along the cap the mass
//! moves first, keeping u; |u| is lowered only where no mass holds it; then I is raised to
//! the disc's), and its certificate is of that design.
//!
//! Hand-written rather than a solver's exponential or power cone: clarabel's power cones are
//! non-symmetric and slower, and S(A) is no standard cone at all.

use super::constraints::Design;
use super::{var_i, var_m, var_u, CounterweightLimits, Engine};
use crate::geom::plate::{cap, cap_areas};
use crate::synth::conic::Rows;
use clarabel::solver::SupportedConeT;

/// A condition broken by more than this fraction of `rel_tol` times its scale (s_I for the
/// inertia, s_u for the first moment) gets tangents about the round's mass.
pub(super) const CUT_TOL: f64 = 1e-4;

/// At most this many tangents of each kind per counterweight.
const MAX_CUTS: usize = 160;

/// The tangents added about a round's mass m: at m(1 + δ) for each δ. One tangent at m
/// alone (Kelley) converges linearly where the design slides along the curved bound, one
/// round per digit; a cluster around m makes the outer approximation tight to
/// ~ S″(mδ)²/8 on both sides at once (δ = 1e-5: 1e-10 of the bound's curvature scale).
const CLUSTER: [f64; 1] = [0.0];

/// Two tangents closer than this fraction of m_max are one.
const SAME_CUT: f64 = 1e-12;

/// The tangent points of one plate counterweight: masses m₀ (kg) of the disc condition's
/// tangents and of the first moment's.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Cuts {
    /// m₀ of each tangent of the disc condition I ≥ |u|²/m + m²/k.
    pub(super) disc: Vec<f64>,
    /// m₀ of each tangent of the cap bound |u| ≤ σ S(m/σ).
    pub(super) cap: Vec<f64>,
}

impl Cuts {
    /// The seeds: m_max·2⁻ᵏ, k = 0..6, for both kinds (none without a plate).
    pub(super) fn seed(c: &CounterweightLimits) -> Cuts {
        if c.plate.is_none() {
            return Cuts::default();
        }
        let pts: Vec<f64> = (0..7).map(|k| c.m_max * 0.5f64.powi(k)).collect();
        Cuts {
            disc: pts.clone(),
            cap: pts,
        }
    }
}

/// k = 2πσ.
fn k_of(sigma: f64) -> f64 {
    std::f64::consts::TAU * sigma
}

/// The tangent of |u| ≤ σ S(m/σ) at m₀: (β, h₀) of |u| ≤ β + h₀ m, β = σ (S₀ − h₀ A₀) ≥ 0.
fn cap_tangent(m0: f64, sigma: f64, r: f64) -> (f64, f64) {
    let c = cap(m0 / sigma, r);
    (sigma * (c.first_moment - c.slope * c.area), c.slope)
}

/// The disc condition's least inertia about the joint, |u|²/m + m²/k (0 at m ≤ 0).
pub(super) fn disc_inertia(m: f64, u2: f64, sigma: f64) -> f64 {
    if m > 0.0 {
        u2 / m + m * m / k_of(sigma)
    } else {
        0.0
    }
}

/// The cap's largest first moment σ S(m/σ) within radius r.
pub(super) fn cap_moment(m: f64, sigma: f64, r: f64) -> f64 {
    sigma * cap((m / sigma).max(0.0), r).first_moment
}

impl<'p, 'a> Engine<'p, 'a> {
    /// Whether any counterweight is a plate.
    pub(super) fn has_plate(&self) -> bool {
        self.pb.counterweights.iter().any(|c| c.plate.is_some())
    }

    /// The plate conditions of counterweight j as smooth constraints in the scaled
    /// variables, in the order of [`Engine::plate_rows`]: a `Radius` per cap tangent
    /// (|û| ≤ c + k m̂), the rim, a `Body` per disc tangent.
    pub(super) fn plate_constraints(&self, j: usize, out: &mut Vec<Design>) {
        let c = &self.pb.counterweights[j];
        let Some(sigma) = c.plate else { return };
        let sc = &self.scale;
        let (m, u, i) = (var_m(j), var_u(j), var_i(j));
        let (sm, su, si) = (sc[m], sc[u], sc[i]);
        let (k, r) = (k_of(sigma), c.envelope);
        let cuts = self.cuts.lock().expect("cuts")[j].clone();
        for &m0 in &cuts.cap {
            let (beta, h0) = cap_tangent(m0, sigma, r);
            out.push(Design::Radius {
                m,
                u,
                k: h0 * sm / su,
                c: beta / su,
            });
        }
        // m̂² ≤ p m̂ − q Î: m² ≤ k (R² m − I) in scaled variables.
        out.push(Design::Rim {
            m,
            i,
            p: k * r * r / sm,
            q: k * si / (sm * sm),
        });
        // (Î − p m̂ + q) m̂ ≥ |û|²: I − (2m₀m − m₀²)/k ≥ |u|²/m in scaled variables.
        for &m0 in &cuts.disc {
            out.push(Design::Body {
                m,
                u,
                i,
                p: 2.0 * m0 * sm / (k * si),
                q: m0 * m0 / (k * si),
            });
        }
    }

    /// The cones of [`Engine::plate_constraints`] (the same constraints, in order).
    pub(super) fn plate_rows(&self, j: usize, rows: &mut Rows) {
        let mut cons = Vec::new();
        self.plate_constraints(j, &mut cons);
        for d in &cons {
            match *d {
                Design::Radius { m, u, k, c } => {
                    rows.row(&[(m, -k)], c);
                    rows.row(&[(u, -1.0)], 0.0);
                    rows.row(&[(u + 1, -1.0)], 0.0);
                    rows.cones.push(SupportedConeT::SecondOrderConeT(3));
                }
                Design::Rim { m, i, p, q } => {
                    // ‖(2m̂, w − 1)‖ ≤ w + 1, w = p m̂ − q Î.
                    rows.row(&[(m, -p), (i, q)], 1.0);
                    rows.row(&[(m, -2.0)], 0.0);
                    rows.row(&[(m, -p), (i, q)], -1.0);
                    rows.cones.push(SupportedConeT::SecondOrderConeT(3));
                }
                Design::Body { m, u, i, p, q } => body_rows(rows, m, u, i, p, q),
                Design::Linear { .. } => unreachable!("no linear plate row"),
            }
        }
    }

    /// Adds a tangent at the mass of design `x` (caller's units, as the solver returned it)
    /// for every plate whose exact condition it breaks by more than [`CUT_TOL`]; whether
    /// any was added.
    pub(super) fn add_plate_cuts(&self, x: &[f64]) -> bool {
        let mut cuts = self.cuts.lock().expect("cuts");
        let mut added = false;
        for (j, c) in self.pb.counterweights.iter().enumerate() {
            let Some(sigma) = c.plate else { continue };
            let (m, u) = (x[var_m(j)], [x[var_u(j)], x[var_u(j) + 1]]);
            if !(m > SAME_CUT * c.m_max) {
                continue;
            }
            let u2 = u[0] * u[0] + u[1] * u[1];
            let short = disc_inertia(m, u2, sigma) - x[var_i(j)];
            let tol = CUT_TOL * self.s.rel_tol;
            if short > tol * self.scale[var_i(j)] {
                added |= push_cuts(&mut cuts[j].disc, m, c.m_max);
            }
            let over = u2.sqrt() - cap_moment(m, sigma, c.envelope);
            if over > tol * self.scale[var_u(j)] {
                // Also where the projection puts the design back on the cap (a supporting
                // tangent at the boundary point, faster than Kelley's alone).
                let mut y = x.to_vec();
                self.project_plate(j, &mut y);
                added |= push_cuts(&mut cuts[j].cap, m, c.m_max);
                added |= push_cuts(&mut cuts[j].cap, y[var_m(j)], c.m_max);
            }
        }
        added
    }

    /// Moves counterweight j's design onto the exact plate conditions (caller's units, in
    /// place): where |u| is more than the cap of its mass holds, the mass moves to the
    /// nearest that holds it (S(A) ≥ |u|/σ on [A_lo, A_hi], [`cap_areas`]), within
    /// [0, m_max], and |u| is lowered to what that mass holds only if none does; then I is
    /// raised to the disc's. Moving m first keeps u, the part of the design most fields see
    /// (a counterweight on a crank turning at constant speed adds ω²·Rot(θ)·u to the force,
    /// whatever its mass).
    pub(super) fn project_plate(&self, j: usize, x: &mut [f64]) {
        let c = &self.pb.counterweights[j];
        let Some(sigma) = c.plate else { return };
        let (m, ux, i) = (var_m(j), var_u(j), var_i(j));
        let norm = x[ux].hypot(x[ux + 1]);
        if norm > cap_moment(x[m], sigma, c.envelope) {
            if let Some((lo, hi)) = cap_areas(norm / sigma, c.envelope) {
                x[m] = x[m].clamp(sigma * lo, sigma * hi).min(c.m_max);
            }
            let most = cap_moment(x[m], sigma, c.envelope);
            if norm > most {
                let f = if norm > 0.0 { most / norm } else { 0.0 };
                x[ux] *= f;
                x[ux + 1] *= f;
            }
        }
        let mass = x[m];
        let u2 = x[ux] * x[ux] + x[ux + 1] * x[ux + 1];
        x[i] = x[i].max(disc_inertia(mass, u2, sigma));
    }
}

/// A rotated cone (Î − p m̂ + q) m̂ ≥ |û|² as ‖(2û, x − m̂)‖ ≤ x + m̂, x = Î − p m̂ + q (the
/// body cone at p = q = 0).
pub(super) fn body_rows(rows: &mut Rows, m: usize, u: usize, i: usize, p: f64, q: f64) {
    rows.row(&[(i, -1.0), (m, p - 1.0)], q);
    rows.row(&[(u, -2.0)], 0.0);
    rows.row(&[(u + 1, -2.0)], 0.0);
    rows.row(&[(i, -1.0), (m, p + 1.0)], q);
    rows.cones.push(SupportedConeT::SecondOrderConeT(4));
}

/// Adds the tangent points of [`CLUSTER`] about m (within (0, m_max]), each unless one is
/// within [`SAME_CUT`]·m_max or there are [`MAX_CUTS`] already; whether any was added.
fn push_cuts(pts: &mut Vec<f64>, m: f64, m_max: f64) -> bool {
    let mut added = false;
    for d in CLUSTER {
        let p = (m * (1.0 + d)).min(m_max);
        if pts.len() >= MAX_CUTS || pts.iter().any(|&q| (q - p).abs() <= SAME_CUT * m_max) {
            continue;
        }
        pts.push(p);
        added = true;
    }
    added
}
