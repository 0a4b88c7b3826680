//! Any one-degree-of-freedom planar linkage (issue 17): a crank driven at constant speed and a
//! chain of Assur dyads, with closed-form kinematics and the shaking force, the shaking moment,
//! the input torque and the joint reactions as **linear maps in the links' inertial
//! parameters** — the form the counterweight cone programs need.
//!
//! Notation (`shared/domain/planar-linkage.md`): θ is the crank angle, ' = d/dθ; at constant
//! speed ω an acceleration is ω² × a second derivative. Link i is a rigid body with a
//! reference joint P_i and an angle ψ_i; its own frame has its origin at P_i and its x axis at
//! ψ_i (along the link's defining direction, see [`Dyad`]). R(ψ) is the rotation, J the
//! rotation by +90° ([`perp`]), e_i = (cos ψ_i, sin ψ_i). A point fixed to link i at `at` in
//! its frame is X = P_i + R(ψ_i)·at.
//!
//! Links are numbered: 0 is the crank (P_0 = the crank pivot A0, ψ_0 = θ), dyad k adds links
//! 2k + 1 and 2k + 2 ([`Linkage::dyad_links`]).
//!
//! Inertial parameters of link i: p_i = (m_i, m_i c_ix, m_i c_iy, I_Pi) with c_i the centroid in
//! the link's frame and I_Pi = J_i + m_i|c_i|² the inertia about P_i ([`Inertia::params`]). A
//! counterweight attached to link i (mass m, centroid q in the link's frame, own centroidal
//! inertia J) adds (m, m q, J + m|q|²) to p_i, so every field below is affine in it.
//!
//! Units: SI throughout (m, kg, kg·m², rad, rad/s, N, N·m); positions and θ-derivatives are
//! pure geometry, the fields ([`Fields`]) carry ω² (and gravity, where it enters).
//!
//! Round-off: each dyad's 2×2 system has the conditioning κ = 1/|sin μ| with μ its
//! transmission angle ([`DyadState::sin_mu`]). Near a toggle the dyad's position loses digits
//! as ε·κ and its derivatives as ε·κ²; a dyad built on an earlier one inherits its error,
//! amplified by κ² again. [`LinkState::amp`] accumulates a_k = κ_k² (1 + a_in) along the chain
//! (a = 1 for the crank) and [`BalanceMap::rho`] turns it into a stated relative error.

use crate::geom::{cmul, cross, perp, solve_columns, Side, P2};
use nalgebra::{Matrix2, Matrix2x4, RowVector4, Vector4};
use std::f64::consts::TAU;

mod lengths;
mod loads;
mod place;
mod reactions;
pub use lengths::tip_of;
pub use loads::ProcessLoad;
pub use place::Place;
pub use reactions::{Body, Joint, JointKind, ReactionMap, Reactions};

/// Inertial parameters of one link, p = (m, m c_x, m c_y, I_P) (kg, kg·m, kg·m, kg·m²).
pub type Params = Vector4<f64>;

/// Where a point of the mechanism is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Point {
    /// Fixed to the frame, in world coordinates (m).
    Frame(P2),
    /// Fixed to moving link `link`, at `at` in the link's own frame (m).
    On {
        /// The link's index (it must be defined before the dyad that uses the point).
        link: usize,
        /// Coordinates in the link's frame (origin P_link, x axis at ψ_link).
        at: P2,
    },
}

impl Point {
    /// The crank pin at radius `r` on the crank's x axis: `On { link: 0, at: (r, 0) }`.
    pub fn crank_pin(r: f64) -> Point {
        Point::On {
            link: 0,
            at: P2::new(r, 0.0),
        }
    }
}

/// An Assur dyad of two links and three joints, adding one new moving joint from two known
/// points. Each dyad adds two links, a (first) and b (second), described per variant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dyad {
    /// Revolute–revolute–revolute: link a of length `l1` pivoted at the known point `p`,
    /// link b of length `l2` pivoted at the known point `q`, joined at the new joint B
    /// (circle–circle, [`circle_circle`]; `side` seen from P towards Q, `Left` =
    /// counter-clockwise). Link a: reference P, x axis P→B, so B = (l1, 0) in its frame.
    /// Link b: reference Q, x axis Q→B, B = (l2, 0).
    Rrr {
        /// P, the pivot of link a.
        p: Point,
        /// l1 = |PB| (m).
        l1: f64,
        /// Q, the pivot of link b.
        q: Point,
        /// l2 = |QB| (m).
        l2: f64,
        /// Assembly branch: the side of the line P→Q on which B lies.
        side: Side,
    },
    /// Revolute–revolute–prismatic: link a (the rod) of length `l` pivoted at the known point
    /// `p`, joined at B to link b (the slider), which translates on the frame line through
    /// `origin` at `angle` (circle–line, [`link_slider`]; `side` `Left` = B further along the
    /// line's direction than the foot of the perpendicular from P). Link a: reference P,
    /// x axis P→B. Link b: reference B, x axis along the line (ψ_b = `angle`, constant).
    /// The slider's position B = origin + t·(cos angle, sin angle) is [`DyadState::var`].
    Rrp {
        /// P, the pivot of the rod.
        p: Point,
        /// l = |PB| (m).
        l: f64,
        /// A point of the slider's line (m, world).
        origin: P2,
        /// The line's direction (rad, world).
        angle: f64,
        /// Assembly branch along the line.
        side: Side,
    },
    /// Revolute–prismatic–revolute: link a (the guide, a slotted link) pivoted at the known
    /// point `p`, along which slides link b (the block), pivoted at the known point `q`. The
    /// guide's slide line runs at the perpendicular distance `offset` from P (to the left of
    /// its direction): Q = P + R(ψ)(s, offset). Link a: reference P, x axis along the slide;
    /// link b: reference Q, the same angle ψ. `side` `Left`: s > 0 (Q ahead of P along the
    /// slide). s is [`DyadState::var`].
    Rpr {
        /// P, the guide's pivot.
        p: Point,
        /// Q, the block's pivot.
        q: Point,
        /// e, offset of the slide line from P (m).
        offset: f64,
        /// Assembly branch: the sign of s.
        side: Side,
    },
}

/// A link's mass properties in its own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    /// m (kg, ≥ 0).
    pub mass: f64,
    /// c, the centroid in the link's frame (m).
    pub centroid: P2,
    /// J, the moment of inertia about the centroid (kg·m², ≥ 0).
    pub j: f64,
}

impl Inertia {
    /// A massless link.
    pub const NONE: Inertia = Inertia {
        mass: 0.0,
        centroid: P2::new(0.0, 0.0),
        j: 0.0,
    };

    /// A uniform bar of length `l` along the link's x axis from its reference joint:
    /// c = (l/2, 0), J = m l²/12.
    pub fn bar(mass: f64, l: f64) -> Inertia {
        Inertia {
            mass,
            centroid: P2::new(0.5 * l, 0.0),
            j: mass * l * l / 12.0,
        }
    }

    /// p = (m, m c_x, m c_y, I_P) with I_P = J + m|c|², the inertia about the reference joint.
    pub fn params(&self) -> Params {
        let u = self.centroid * self.mass;
        Params::new(
            self.mass,
            u.x,
            u.y,
            self.j + self.mass * self.centroid.norm_squared(),
        )
    }
}

/// Why a linkage description is not usable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinkageError {
    /// A link without a length (a slider, a guide, a block) was given one.
    #[error("link {link} has no length (only the crank, RRR links and RRP rods have one)")]
    NoLength {
        /// The link.
        link: usize,
    },
    /// A slider's line was asked of a link that is not a slider.
    #[error("link {link} is not a slider (the second link of an RRP dyad)")]
    NotSlider {
        /// The link.
        link: usize,
    },
    /// A dyad uses a point on a link that is not yet defined.
    #[error("dyad {dyad} uses a point on link {link}, which is not defined before it (links 0..{known})")]
    ForwardReference {
        /// The dyad.
        dyad: usize,
        /// The link it names.
        link: usize,
        /// The number of links defined before the dyad.
        known: usize,
    },
    /// A length, offset, angle or coordinate is not finite, or a length not positive.
    #[error("dyad {dyad}: {what} = {value} is invalid")]
    BadDyad {
        /// The dyad.
        dyad: usize,
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The inertial data list does not have one entry per link.
    #[error("{got} inertia entries for {expected} links")]
    InertiaCount {
        /// 1 + 2 × dyads.
        expected: usize,
        /// Given.
        got: usize,
    },
    /// A mass or inertia is negative or not finite.
    #[error("link {link}: {what} = {value} is invalid")]
    BadInertia {
        /// The link.
        link: usize,
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The speed, the pivot or the gravity vector is not finite.
    #[error("{what} is not finite")]
    NotFinite {
        /// The quantity.
        what: &'static str,
    },
    /// [`Linkage::berkof_lowen`] needs a four-bar: one RRR dyad joining a crank point to a
    /// frame point.
    #[error("not a four-bar (one RRR dyad from a crank point to a frame point)")]
    NotFourBar,
    /// The joint-force equations are singular at θ (a toggle: the dyads carry no load there).
    #[error("the joint-force equations are singular at theta = {theta}")]
    SingularReactions {
        /// θ (rad).
        theta: f64,
    },
    /// A process load's link, point, direction or table is invalid.
    #[error("process load {load}: its link, point, direction or table is invalid")]
    BadLoad {
        /// The load's index.
        load: usize,
    },
}

/// A dyad that does not assemble at θ: a value, never a NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoAssembly {
    /// θ (rad).
    pub theta: f64,
    /// The first dyad that fails.
    pub dyad: usize,
    /// How far the dyad is from assembling (m, ≥ 0): RRR max(|PQ| − (l1 + l2), |l1 − l2| −
    /// |PQ|); RRP |dist(P, line)| − l; RPR |e| − |PQ|. 0 when it assembles exactly at a
    /// toggle (determinant zero: the derivatives are infinite) or P = Q.
    pub gap: f64,
}

/// A range of crank angles where the linkage cannot assemble.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unreachable {
    /// First unreachable angle (rad, in [0, 2π)).
    pub from: f64,
    /// Last unreachable angle (rad, in (from, from + 2π]; above 2π the range wraps past 0).
    pub to: f64,
    /// The dyad that fails in the middle of the range.
    pub dyad: usize,
}

/// A one-degree-of-freedom planar linkage: crank + dyads + mass properties + speed.
#[derive(Debug, Clone, PartialEq)]
pub struct Linkage {
    pivot: P2,
    dyads: Vec<Dyad>,
    inertia: Vec<Inertia>,
    omega: f64,
    gravity: P2,
    /// Process loads ([`Linkage::with_loads`]); none by default.
    loads: Vec<ProcessLoad>,
}

/// One link's state at θ: its reference joint, its angle and their θ-derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkState {
    /// P, P', P'' (m, m/rad, m/rad²).
    pub p: [P2; 3],
    /// ψ, ψ', ψ''; ψ in (−π, π] for dyad links (θ itself for the crank).
    pub psi: [f64; 3],
    /// e = (cos ψ, sin ψ), computed from the construction (not from ψ).
    pub e: P2,
    /// Round-off amplification a of this link's state (1 for the crank, see the module doc).
    pub amp: f64,
}

impl LinkState {
    /// The point fixed at `at` in the link's frame, with its derivatives:
    /// X = P + R(ψ) at, X' = P' + ψ' J R at, X'' = P'' + ψ'' J R at − ψ'² R at.
    pub fn point(&self, at: P2) -> [P2; 3] {
        let r = cmul(self.e, at);
        let jr = perp(r);
        [
            self.p[0] + r,
            self.p[1] + jr * self.psi[1],
            self.p[2] + jr * self.psi[2] - r * (self.psi[1] * self.psi[1]),
        ]
    }

    /// R(ψ) as a matrix.
    pub fn rot(&self) -> Matrix2<f64> {
        Matrix2::new(self.e.x, -self.e.y, self.e.y, self.e.x)
    }
}

/// One dyad's state at θ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DyadState {
    /// The dyad's inner joint and its derivatives: B for RRR and RRP, Q (the block's pivot on
    /// the guide) for RPR.
    pub joint: [P2; 3],
    /// The joint variable and its derivatives: RRR μ = ψ_b − ψ_a (the transmission angle,
    /// in (−π, π]); RRP t (m, slider position along its line); RPR s (m, along the guide).
    pub var: [f64; 3],
    /// sin μ, the sine of the angle between the columns of the dyad's 2×2 system (its
    /// determinant over the product of the columns' lengths): RRR sin(ψ_b − ψ_a), RRP
    /// e_a·u (the rod against the line's normal), RPR −s/|PQ|. 0 at a toggle.
    pub sin_mu: f64,
}

impl DyadState {
    /// κ = 1/|sin μ|, the dyad's conditioning (1 at best, ∞ at a toggle).
    pub fn kappa(&self) -> f64 {
        1.0 / self.sin_mu.abs()
    }
}

/// The whole mechanism at one crank angle.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// θ (rad).
    pub theta: f64,
    /// Every link, crank first ([`Linkage::dyad_links`]).
    pub links: Vec<LinkState>,
    /// Every dyad, in order.
    pub dyads: Vec<DyadState>,
}

impl Pose {
    /// The largest dyad conditioning κ at this angle (1 without dyads).
    pub fn kappa(&self) -> f64 {
        self.dyads.iter().map(DyadState::kappa).fold(1.0, f64::max)
    }

    /// The largest round-off amplification a over the links (see the module doc).
    pub fn amp(&self) -> f64 {
        self.links.iter().map(|l| l.amp).fold(1.0, f64::max)
    }

    /// A point and its θ-derivatives.
    pub fn point(&self, pt: &Point) -> [P2; 3] {
        match *pt {
            Point::Frame(x) => [x, P2::zeros(), P2::zeros()],
            Point::On { link, at } => self.links[link].point(at),
        }
    }

    /// Round-off amplification of a point's state (0 on the frame).
    fn amp_of(&self, pt: &Point) -> f64 {
        match *pt {
            Point::Frame(_) => 0.0,
            Point::On { link, .. } => self.links[link].amp,
        }
    }
}

/// Shaking force, shaking moment and input torque at one angle (N, N·m, N·m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fields {
    /// F = −Σ m_i r̈_Gi: the inertial force of the moving links on the frame (the weights, a
    /// static load, are not part of it, nor of the moment).
    pub force: P2,
    /// M_O = −Σ [(r_Gi − O) × m_i r̈_Gi + J_i ψ̈_i] about the map's point O (counter-clockwise
    /// positive): the inertial moment the frame feels, the motor's reaction included. The
    /// pin forces alone give M_O + T.
    pub moment: f64,
    /// T = ω² Σ [m_i r'_Gi·r''_Gi + J_i ψ'_i ψ''_i] − Σ m_i g·r'_Gi − Σ F_L·X'_L: the input
    /// torque on the crank at constant speed (inertia, weights and process loads).
    pub torque: f64,
}

/// A linkage's terms for the drive at one crank angle ([`Linkage::drive_terms`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DriveTerms {
    /// J, the generalised inertia (kg·m²).
    pub j: f64,
    /// J' = dJ/dθ (kg·m²).
    pub dj: f64,
    /// G = V', the weights' torque on the crank (N·m).
    pub g: f64,
    /// Σ m r_G', the momentum per unit crank speed (kg·m).
    pub momentum: P2,
    /// Σ m r_G'', its θ-derivative (kg·m).
    pub momentum_rate: P2,
}

/// The linear maps of one link's parameters p_i into the fields: F += A p_i, M_O += m p_i,
/// T += t p_i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blocks {
    /// A_i = −ω² [P'' | E2 | 0] with E2 = ψ'' J R − ψ'² R (r_G'' = P'' + E2 c), 2×4.
    pub force: Matrix2x4<f64>,
    /// M_O row: with the inertial wrench (F_i, M_Pi) of link i about P_i,
    /// M_O,i = M_Pi + (P_i − O) × F_i, where
    /// M_Pi = −ω² [(R u) × P'' + I_P ψ''] (u = m c), so the row is
    /// [−ω² (P − O) × P'', ω² (Rᵀ J P'')ᵀ + (P − O) × (−ω² E2 columns), −ω² ψ''].
    pub moment: RowVector4<f64>,
    /// T row, from the kinetic and potential energy: m r'_G·r''_G + J ψ'ψ'' =
    /// m P'·P'' + (E2ᵀ P' − ψ' Rᵀ J P'')·u + ψ'ψ'' I_P (the m|c|² terms join J into I_P), so
    /// t = [ω² P'·P'' − g·P', ω² (E2ᵀ P' − ψ' Rᵀ J P'')ᵀ + ψ' (Rᵀ J g)ᵀ, ω² ψ'ψ''].
    pub torque: RowVector4<f64>,
}

/// The fields at one angle as an affine map of the links' parameters: everything a
/// counterweight program needs at a sample.
#[derive(Debug, Clone, PartialEq)]
pub struct BalanceMap {
    /// θ (rad).
    pub theta: f64,
    /// O, the point the moment is taken about (m).
    pub o: P2,
    /// The bare linkage's fields, Σ_i blocks_i p_i.
    pub base: Fields,
    /// Per link (crank first): the blocks of its parameter vector.
    pub blocks: Vec<Blocks>,
    /// The largest dyad conditioning κ at θ.
    pub kappa: f64,
    /// ρ: a relative round-off bound for every block: for any parameters p, the computed
    /// Σ_i A_i p_i differs from the exact one by at most ρ Σ_i ‖A_i‖_F ‖p_i‖ (Frobenius
    /// and Euclidean norms), likewise the moment and torque rows. ρ = 64 ε a with a the
    /// largest round-off amplification of the pose ([`Pose::amp`]).
    /// Measured (`tests/linkage_model.rs`): at most 0.08 ρ against a double-double reference
    /// of a four-bar up to κ ≈ 4·10⁵, and 0.02 ρ between rotated copies near the limits of
    /// every dyad kind.
    pub rho: f64,
    /// The process loads' torque T_L = −Σ F·X′ (N·m), in `base.torque`
    /// ([`Linkage::load_torque`]).
    pub load_torque: f64,
    /// Its scale Σ |F|·|X′| (N·m), for the round-off bound.
    pub load_scale: f64,
}

impl BalanceMap {
    /// F, M_O, T with `extra[j] = (link, x)` added to the parameters of `link` (e.g.
    /// counterweights): base + Σ_j blocks_link x_j.
    pub fn fields(&self, extra: &[(usize, Params)]) -> Fields {
        let mut f = self.base;
        for (i, x) in extra {
            self.add(&mut f, *i, x);
        }
        f
    }

    /// f += blocks_i x: link i's parameters `x` added to the fields `f`.
    fn add(&self, f: &mut Fields, i: usize, x: &Params) {
        let b = &self.blocks[i];
        let fx = b.force * x;
        f.force += P2::new(fx[0], fx[1]);
        f.moment += b.moment.dot(&x.transpose());
        f.torque += b.torque.dot(&x.transpose());
    }

    /// The round-off bound on [`BalanceMap::fields`] with `extra` (see [`BalanceMap::rho`]),
    /// as (force magnitude, moment, torque).
    pub fn error(&self, params: &[Params], extra: &[(usize, Params)]) -> (f64, f64, f64) {
        let mut s = (0.0, 0.0, 0.0);
        let mut add = |b: &Blocks, p: &Params| {
            let n = p.norm();
            s.0 += b.force.norm() * n;
            s.1 += b.moment.norm() * n;
            s.2 += b.torque.norm() * n;
        };
        for (b, p) in self.blocks.iter().zip(params) {
            add(b, p);
        }
        for (i, x) in extra {
            add(&self.blocks[*i], x);
        }
        (
            self.rho * s.0,
            self.rho * s.1,
            self.rho * (s.2 + self.load_scale),
        )
    }
}

/// A four-bar's full force balance (Berkof–Lowen), as first moments in the links' frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceBalance {
    /// The crank's total first moment u_2 = q_A ⊗ (u_3/a3 − m3) (kg·m, crank frame; q_A is
    /// the crank pin in the crank's frame, ⊗ the complex product; for q_A = (a2, 0) it is
    /// m3 a2 ((r3/a3) e^{iφ3} − 1)).
    pub crank: P2,
    /// The rocker's total first moment u_4 = −(a4/a3) u_3 (kg·m, rocker frame).
    pub rocker: P2,
    /// What a crank counterweight must add: u_2 − m2 c2.
    pub crank_add: P2,
    /// What a rocker counterweight must add: u_4 − m4 c4.
    pub rocker_add: P2,
    /// The crank link (0) and the rocker link.
    pub links: (usize, usize),
}

impl Linkage {
    /// A checked linkage: crank pivot A0, dyads, one [`Inertia`] per link (crank first), the
    /// constant crank speed ω (rad/s) and gravity g (m/s², world; zero for none).
    pub fn new(
        pivot: P2,
        dyads: Vec<Dyad>,
        inertia: Vec<Inertia>,
        omega: f64,
        gravity: P2,
    ) -> Result<Linkage, LinkageError> {
        let finite = |v: P2| v.x.is_finite() && v.y.is_finite();
        if !finite(pivot) {
            return Err(LinkageError::NotFinite { what: "pivot" });
        }
        if !omega.is_finite() {
            return Err(LinkageError::NotFinite { what: "omega" });
        }
        if !finite(gravity) {
            return Err(LinkageError::NotFinite { what: "gravity" });
        }
        for (k, d) in dyads.iter().enumerate() {
            let known = 1 + 2 * k;
            let point = |pt: &Point, what: &'static str| match *pt {
                Point::Frame(x) if !finite(x) => Err(LinkageError::BadDyad {
                    dyad: k,
                    what,
                    value: f64::NAN,
                }),
                Point::On { link, .. } if link >= known => Err(LinkageError::ForwardReference {
                    dyad: k,
                    link,
                    known,
                }),
                Point::On { at, .. } if !finite(at) => Err(LinkageError::BadDyad {
                    dyad: k,
                    what,
                    value: f64::NAN,
                }),
                _ => Ok(()),
            };
            let length = |l: f64, what: &'static str| {
                if l > 0.0 && l.is_finite() {
                    Ok(())
                } else {
                    Err(LinkageError::BadDyad {
                        dyad: k,
                        what,
                        value: l,
                    })
                }
            };
            match d {
                Dyad::Rrr { p, l1, q, l2, .. } => {
                    point(p, "p")?;
                    point(q, "q")?;
                    length(*l1, "l1")?;
                    length(*l2, "l2")?;
                }
                Dyad::Rrp {
                    p,
                    l,
                    origin,
                    angle,
                    ..
                } => {
                    point(p, "p")?;
                    length(*l, "l")?;
                    if !finite(*origin) {
                        return Err(LinkageError::BadDyad {
                            dyad: k,
                            what: "origin",
                            value: f64::NAN,
                        });
                    }
                    if !angle.is_finite() {
                        return Err(LinkageError::BadDyad {
                            dyad: k,
                            what: "angle",
                            value: *angle,
                        });
                    }
                }
                Dyad::Rpr { p, q, offset, .. } => {
                    point(p, "p")?;
                    point(q, "q")?;
                    if !offset.is_finite() {
                        return Err(LinkageError::BadDyad {
                            dyad: k,
                            what: "offset",
                            value: *offset,
                        });
                    }
                }
            }
        }
        let expected = 1 + 2 * dyads.len();
        if inertia.len() != expected {
            return Err(LinkageError::InertiaCount {
                expected,
                got: inertia.len(),
            });
        }
        let mut l = Linkage {
            pivot,
            dyads,
            inertia: Vec::new(),
            omega,
            gravity,
            loads: Vec::new(),
        };
        l.inertia = vec![Inertia::NONE; expected];
        for (i, m) in inertia.into_iter().enumerate() {
            l.set_inertia(i, m)?;
        }
        Ok(l)
    }

    /// Replaces link `link`'s mass properties (checked: m, J ≥ 0 and finite).
    pub fn set_inertia(&mut self, link: usize, m: Inertia) -> Result<(), LinkageError> {
        let bad = |what, value| Err(LinkageError::BadInertia { link, what, value });
        if link >= self.inertia.len() {
            return bad("index", link as f64);
        }
        if !(m.mass >= 0.0 && m.mass.is_finite()) {
            return bad("mass", m.mass);
        }
        if !(m.j >= 0.0 && m.j.is_finite()) {
            return bad("inertia", m.j);
        }
        if !(m.centroid.x.is_finite() && m.centroid.y.is_finite()) {
            return bad("centroid", f64::NAN);
        }
        self.inertia[link] = m;
        Ok(())
    }

    /// Sets the crank speed ω (rad/s, finite).
    pub fn set_omega(&mut self, omega: f64) -> Result<(), LinkageError> {
        if !omega.is_finite() {
            return Err(LinkageError::NotFinite { what: "omega" });
        }
        self.omega = omega;
        Ok(())
    }

    /// The crank pivot A0.
    pub fn pivot(&self) -> P2 {
        self.pivot
    }
    /// The dyads.
    pub fn dyads(&self) -> &[Dyad] {
        &self.dyads
    }
    /// The links' mass properties (crank first).
    pub fn inertia(&self) -> &[Inertia] {
        &self.inertia
    }
    /// ω (rad/s).
    pub fn omega(&self) -> f64 {
        self.omega
    }
    /// g (m/s², world).
    pub fn gravity(&self) -> P2 {
        self.gravity
    }
    /// The number of links, 1 + 2 × dyads.
    pub fn n_links(&self) -> usize {
        1 + 2 * self.dyads.len()
    }
    /// The links (a, b) that dyad `k` adds: (2k + 1, 2k + 2).
    pub fn dyad_links(k: usize) -> (usize, usize) {
        (2 * k + 1, 2 * k + 2)
    }
    /// Every link's parameter vector p_i ([`Inertia::params`]).
    pub fn params(&self) -> Vec<Params> {
        self.inertia.iter().map(Inertia::params).collect()
    }

    /// Positions and θ-derivatives of every link at crank angle θ, or the first dyad that
    /// does not assemble.
    ///
    /// Positions from the closed-form constructions (`model/place.rs`, shared with
    /// [`Linkage::places`]); derivatives from the differentiated loop
    /// equations, one 2×2 system per dyad solved by [`solve_columns`] with the same matrix for
    /// both orders:
    /// - RRR, B = P + l1 e_a = Q + l2 e_b: [l1 J e_a, −l2 J e_b](ψ_a', ψ_b') = Q' − P', and
    ///   (ψ_a'', ψ_b'') with the right side Q'' − P'' + l1 ψ_a'² e_a − l2 ψ_b'² e_b;
    /// - RRP, B = P + l e_a = origin + t u: [l J e_a, −u](ψ_a', t') = −P', right side
    ///   −P'' + l ψ_a'² e_a for (ψ_a'', t'');
    /// - RPR, v = Q − P = R(ψ)(s, e): [J v, e_ψ](ψ', s') = Q' − P', right side
    ///   Q'' − P'' + ψ'² v − 2 s'ψ' J e_ψ for (ψ'', s'').
    ///
    /// The branch of each dyad is fixed by its `side`, which a continuous motion changes only
    /// through a toggle, so the poses at successive angles lie on one branch.
    pub fn pose(&self, theta: f64) -> Result<Pose, NoAssembly> {
        self.pose_with(theta, true)
    }

    /// [`Linkage::pose`] without the angles: every dyad link's ψ (`psi[0]`) and every RRR
    /// dyad's μ (`var[0]`) are NaN — the three `atan2` of a four-bar's pose, which neither
    /// the fields' balance maps nor the reactions read (they use the directions e and the
    /// derivatives); everything else bit for bit [`Linkage::pose`]'s.
    pub fn pose_for_fields(&self, theta: f64) -> Result<Pose, NoAssembly> {
        self.pose_with(theta, false)
    }

    fn pose_with(&self, theta: f64, angles: bool) -> Result<Pose, NoAssembly> {
        let psi0 = |e: P2| if angles { e.y.atan2(e.x) } else { f64::NAN };
        let (s, c) = theta.sin_cos();
        let mut pose = Pose {
            theta,
            links: Vec::with_capacity(self.n_links()),
            dyads: Vec::with_capacity(self.dyads.len()),
        };
        pose.links.push(LinkState {
            p: [self.pivot, P2::zeros(), P2::zeros()],
            psi: [theta, 1.0, 0.0],
            e: P2::new(c, s),
            amp: 1.0,
        });
        for (k, d) in self.dyads.iter().enumerate() {
            let fail = |gap: f64| NoAssembly {
                theta,
                dyad: k,
                gap: gap.max(0.0),
            };
            match *d {
                Dyad::Rrr { p, l1, q, l2, side } => {
                    let (pp, qq) = (pose.point(&p), pose.point(&q));
                    let placed = place::rrr(pp[0], l1, qq[0], l2, side).map_err(fail)?;
                    let (b, ea, eb, gap) = (placed.joint, placed.a.e, placed.b.e, placed.gap);
                    let (ca, cb) = (perp(ea) * l1, -perp(eb) * l2);
                    let (wa1, wb1) = solve_columns(ca, cb, qq[1] - pp[1]).ok_or(fail(gap))?;
                    let w2 = qq[2] - pp[2] + ea * (l1 * wa1 * wa1) - eb * (l2 * wb1 * wb1);
                    let (wa2, wb2) = solve_columns(ca, cb, w2).ok_or(fail(gap))?;
                    let sin_mu = placed.sin_mu;
                    if sin_mu == 0.0 {
                        return Err(fail(0.0));
                    }
                    let amp = sin_mu.powi(-2) * (1.0 + pose.amp_of(&p).max(pose.amp_of(&q)));
                    let (psa, psb) = (psi0(ea), psi0(eb));
                    pose.links.push(LinkState {
                        p: pp,
                        psi: [psa, wa1, wa2],
                        e: ea,
                        amp,
                    });
                    pose.links.push(LinkState {
                        p: qq,
                        psi: [psb, wb1, wb2],
                        e: eb,
                        amp,
                    });
                    let joint = pose.links[pose.links.len() - 2].point(P2::new(l1, 0.0));
                    let mu = match angles {
                        true => sin_mu.atan2(ea.dot(&eb)),
                        false => f64::NAN,
                    };
                    pose.dyads.push(DyadState {
                        joint: [b, joint[1], joint[2]],
                        var: [mu, wb1 - wa1, wb2 - wa2],
                        sin_mu,
                    });
                }
                Dyad::Rrp {
                    p,
                    l,
                    origin,
                    angle,
                    side,
                } => {
                    let pp = pose.point(&p);
                    let placed = place::rrp(pp[0], l, origin, angle, side).map_err(fail)?;
                    let (b, ea, u) = (placed.joint, placed.a.e, placed.b.e);
                    let (ca, cb) = (perp(ea) * l, -u);
                    let (wa1, t1) = solve_columns(ca, cb, -pp[1]).ok_or(fail(0.0))?;
                    let w2 = -pp[2] + ea * (l * wa1 * wa1);
                    let (wa2, t2) = solve_columns(ca, cb, w2).ok_or(fail(0.0))?;
                    let sin_mu = placed.sin_mu;
                    if sin_mu == 0.0 {
                        return Err(fail(0.0));
                    }
                    let amp = sin_mu.powi(-2) * (1.0 + pose.amp_of(&p));
                    pose.links.push(LinkState {
                        p: pp,
                        psi: [psi0(ea), wa1, wa2],
                        e: ea,
                        amp,
                    });
                    let bj = [b, u * t1, u * t2];
                    pose.links.push(LinkState {
                        p: bj,
                        psi: [angle, 0.0, 0.0],
                        e: u,
                        amp,
                    });
                    pose.dyads.push(DyadState {
                        joint: bj,
                        var: [(b - origin).dot(&u), t1, t2],
                        sin_mu,
                    });
                }
                Dyad::Rpr { p, q, offset, side } => {
                    let (pp, qq) = (pose.point(&p), pose.point(&q));
                    let placed = place::rpr(pp[0], qq[0], offset, side).map_err(fail)?;
                    let (v, eg, s) = (qq[0] - pp[0], placed.a.e, placed.slide);
                    let (ca, cb) = (perp(v), eg);
                    let (w1, s1) = solve_columns(ca, cb, qq[1] - pp[1]).ok_or(fail(0.0))?;
                    let rhs = qq[2] - pp[2] + v * (w1 * w1) - perp(eg) * (2.0 * s1 * w1);
                    let (w2, s2d) = solve_columns(ca, cb, rhs).ok_or(fail(0.0))?;
                    let sin_mu = placed.sin_mu;
                    if sin_mu == 0.0 {
                        return Err(fail(0.0));
                    }
                    let amp = sin_mu.powi(-2) * (1.0 + pose.amp_of(&p).max(pose.amp_of(&q)));
                    let psi = [psi0(eg), w1, w2];
                    pose.links.push(LinkState {
                        p: pp,
                        psi,
                        e: eg,
                        amp,
                    });
                    pose.links.push(LinkState {
                        p: qq,
                        psi,
                        e: eg,
                        amp,
                    });
                    pose.dyads.push(DyadState {
                        joint: qq,
                        var: [s, s1, s2d],
                        sin_mu,
                    });
                }
            }
        }
        Ok(pose)
    }

    /// The crank angles where the linkage cannot assemble, over one turn.
    ///
    /// `samples` equally spaced angles (at least 8 are used) find the failing runs; each end
    /// is then bisected between the last assembling and the first failing angle until the
    /// bracket is below `tol` (rad), and the range reported is the failing side of both
    /// brackets, so each end is within `tol` of the true limit. A range narrower than the
    /// sample spacing 2π/`samples` can be missed. Empty when the crank turns fully; one range
    /// [0, 2π] when no angle assembles. An angle assembles where [`Linkage::places`] does
    /// (positions only).
    pub fn unreachable(&self, samples: usize, tol: f64) -> Vec<Unreachable> {
        let n = samples.max(8);
        let h = TAU / n as f64;
        let ok: Vec<bool> = (0..n).map(|k| self.places(k as f64 * h).is_ok()).collect();
        let dyad_at = |t: f64| self.places(t).err().map_or(0, |f| f.dyad);
        let Some(first_ok) = ok.iter().position(|&b| b) else {
            return vec![Unreachable {
                from: 0.0,
                to: TAU,
                dyad: dyad_at(0.0),
            }];
        };
        let tol = tol.max(1e-15);
        // Bisects [good, bad] (either order) to the failing end.
        let bisect = |mut good: f64, mut bad: f64| {
            while (bad - good).abs() > tol {
                let mid = 0.5 * (good + bad);
                if mid == good || mid == bad {
                    break;
                }
                if self.places(mid).is_ok() {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            bad
        };
        let mut out = Vec::new();
        let mut k = 0;
        while k < n {
            let i = (first_ok + k) % n;
            if ok[i] {
                k += 1;
                continue;
            }
            // A failing run from sample index first_ok + k to first_ok + j − 1 (unwrapped).
            let mut j = k;
            while j < n && !ok[(first_ok + j) % n] {
                j += 1;
            }
            let t_start = (first_ok + k) as f64 * h;
            let t_end = (first_ok + j - 1) as f64 * h;
            let from = bisect(t_start - h, t_start);
            let to = bisect(t_end + h, t_end);
            let shift = from.div_euclid(TAU) * TAU;
            out.push(Unreachable {
                from: from - shift,
                to: to - shift,
                dyad: dyad_at(0.5 * (from + to)),
            });
            k = j;
        }
        out
    }

    /// The fields' linear maps at a pose, with the moment about `o`: [`BalanceMap`].
    pub fn balance_map(&self, pose: &Pose, o: P2) -> BalanceMap {
        let w2 = self.omega * self.omega;
        let g = self.gravity;
        let blocks: Vec<Blocks> = pose
            .links
            .iter()
            .map(|ls| {
                let (fm, mp) = inertial_wrench(ls, w2);
                let d = ls.p[0] - o;
                let mut moment = mp;
                for c in 0..4 {
                    moment[c] += cross(d, P2::new(fm[(0, c)], fm[(1, c)]));
                }
                let rt = ls.rot().transpose();
                let p1 = ls.p[1];
                let e2 = e2_matrix(ls);
                let tu = (e2.transpose() * p1 - rt * perp(ls.p[2]) * ls.psi[1]) * w2
                    + rt * perp(g) * ls.psi[1];
                let torque = RowVector4::new(
                    w2 * p1.dot(&ls.p[2]) - g.dot(&p1),
                    tu.x,
                    tu.y,
                    w2 * ls.psi[1] * ls.psi[2],
                );
                Blocks {
                    force: fm,
                    moment,
                    torque,
                }
            })
            .collect();
        let mut map = BalanceMap {
            theta: pose.theta,
            o,
            base: Fields {
                force: P2::zeros(),
                moment: 0.0,
                torque: 0.0,
            },
            blocks,
            kappa: pose.kappa(),
            rho: 64.0 * f64::EPSILON * pose.amp(),
            load_torque: 0.0,
            load_scale: 0.0,
        };
        let mut base = map.base;
        for (i, m) in self.inertia.iter().enumerate() {
            map.add(&mut base, i, &m.params());
        }
        map.base = base;
        (map.load_torque, map.load_scale) = self.load_torque(pose);
        map.base.torque += map.load_torque;
        map
    }

    /// The fields of the bare linkage at θ, moment about `o`.
    pub fn fields(&self, theta: f64, o: P2) -> Result<Fields, NoAssembly> {
        Ok(self.balance_map(&self.pose(theta)?, o).base)
    }

    /// The machine's terms for the drive at a pose (`crate::dynamics::OneDof`), with `extra`
    /// added to the links' parameters as in [`BalanceMap::fields`]. Per link, with
    /// p = (m, u, I_P), R u the first moment in the world and J the rotation by +90°:
    /// - J(θ) = Σ [m |P'|² + 2 ψ' P'·(J R u) + I_P ψ'²], the generalised inertia
    ///   Σ (m |r_G'|² + J_G ψ'²);
    /// - J'(θ) = 2 Σ [m P'·P'' + (E2ᵀ P' − ψ' Rᵀ J P'')·u + I_P ψ' ψ''], twice the inertial
    ///   part of the torque row over ω² ([`Blocks::torque`]);
    /// - G(θ) = V' = Σ [−m g·P' + ψ' (Rᵀ J g)·u], the weights' part of it;
    /// - the momentum and its derivative, Σ m r_G' = Σ (m P' + ψ' J R u) and
    ///   Σ m r_G'' = Σ (m P'' + E2 u), so that at real speed the shaking force is
    ///   F = −(ω² Σ m r_G'' + α Σ m r_G');
    /// - G also carries the process loads' torque T_L = −Σ F·X′ ([`Linkage::load_torque`]).
    pub fn drive_terms(&self, pose: &Pose, extra: &[(usize, Params)]) -> DriveTerms {
        let g = self.gravity;
        let mut t = DriveTerms::default();
        let own = self.params().into_iter().enumerate();
        for (i, p) in own.chain(extra.iter().copied()) {
            let ls = &pose.links[i];
            let (m, u, ip) = (p[0], P2::new(p[1], p[2]), p[3]);
            let ru = cmul(ls.e, u);
            let (p1, p2, w1, w2) = (ls.p[1], ls.p[2], ls.psi[1], ls.psi[2]);
            let e2u = perp(ru) * w2 - ru * (w1 * w1);
            t.j += m * p1.norm_squared() + 2.0 * w1 * p1.dot(&perp(ru)) + ip * w1 * w1;
            t.dj += 2.0 * (m * p1.dot(&p2) + p1.dot(&e2u) + w1 * p2.dot(&perp(ru)) + ip * w1 * w2);
            t.g += -m * g.dot(&p1) - w1 * g.dot(&perp(ru));
            t.momentum += p1 * m + perp(ru) * w1;
            t.momentum_rate += p2 * m + e2u;
        }
        t.g += self.load_torque(pose).0;
        t
    }

    /// Berkof–Lowen full force balance of a four-bar (a crank and one RRR dyad joining a crank
    /// point to a frame point, in either order): the first moments the crank and the rocker
    /// must have for the total centre of mass to stay fixed for every motion,
    /// u_2 = q_A ⊗ (u_3/a3 − m3), u_4 = −(a4/a3) u_3, from eliminating e^{iθ3} with the loop
    /// equation (`shared/domain/planar-linkage.md`). The coupler is the dyad link pivoted at
    /// the crank point, a3 its length; the rocker is the other, a4 its length. The crank and
    /// rocker masses do not enter (their pivots are fixed), nor does any inertia.
    pub fn berkof_lowen(&self) -> Result<ForceBalance, LinkageError> {
        let [Dyad::Rrr { p, l1, q, l2, .. }] = self.dyads.as_slice() else {
            return Err(LinkageError::NotFourBar);
        };
        let (a, b) = Self::dyad_links(0);
        // (crank point, coupler link, a3, rocker link, a4)
        let (qa, coupler, a3, rocker, a4) = match (p, q) {
            (Point::On { link: 0, at }, Point::Frame(_)) => (*at, a, *l1, b, *l2),
            (Point::Frame(_), Point::On { link: 0, at }) => (*at, b, *l2, a, *l1),
            _ => return Err(LinkageError::NotFourBar),
        };
        let m3 = self.inertia[coupler].mass;
        let u3 = self.inertia[coupler].centroid * m3;
        let crank = cmul(qa, u3 / a3 - P2::new(m3, 0.0));
        let rocker_u = -u3 * (a4 / a3);
        let own = |i: usize| self.inertia[i].centroid * self.inertia[i].mass;
        Ok(ForceBalance {
            crank,
            rocker: rocker_u,
            crank_add: crank - own(0),
            rocker_add: rocker_u - own(rocker),
            links: (0, rocker),
        })
    }
}

/// E2 = ψ'' J R − ψ'² R, so that d²/dθ² (R(ψ) c) = E2 c.
fn e2_matrix(ls: &LinkState) -> Matrix2<f64> {
    let r = ls.rot();
    let jr = Matrix2::new(-ls.e.y, -ls.e.x, ls.e.x, -ls.e.y);
    jr * ls.psi[2] - r * (ls.psi[1] * ls.psi[1])
}

/// The inertial (d'Alembert) wrench of a link at constant speed ω (`w2` = ω²):
/// [`inertial_wrench_at`] with α = 0.
fn inertial_wrench(ls: &LinkState, w2: f64) -> (Matrix2x4<f64>, RowVector4<f64>) {
    inertial_wrench_at(ls, w2, 0.0)
}

/// The inertial (d'Alembert) wrench of a link at speed ω (`w2` = ω²) and angular
/// acceleration α of the crank, as linear maps of p = (m, u, I_P): every second time
/// derivative is (·)''ω² + (·)'α, so with A = P''ω² + P'α, E = E2 ω² + E1 α (E1 = ψ' J R,
/// d/dθ (R c) = E1 c) and ψ̈ = ψ''ω² + ψ'α the force is −(m A + E u) (2×4) and its moment
/// about P is −[(R u) × A + I_P ψ̈] (1×4), using (R u) × A = −(Rᵀ J A)·u. At α = 0 these are
/// the constant-speed maps bit for bit (the α terms are exact zeros).
pub(crate) fn inertial_wrench_at(
    ls: &LinkState,
    w2: f64,
    alpha: f64,
) -> (Matrix2x4<f64>, RowVector4<f64>) {
    let r = ls.rot();
    let jr = Matrix2::new(-ls.e.y, -ls.e.x, ls.e.x, -ls.e.y);
    let e = -(e2_matrix(ls) * w2 + jr * (ls.psi[1] * alpha));
    let a = -(ls.p[2] * w2 + ls.p[1] * alpha);
    let force = Matrix2x4::new(
        a.x,
        e[(0, 0)],
        e[(0, 1)],
        0.0,
        a.y,
        e[(1, 0)],
        e[(1, 1)],
        0.0,
    );
    let rt = r.transpose();
    let rj = rt * perp(ls.p[2]) * w2 + rt * perp(ls.p[1]) * alpha;
    let moment = RowVector4::new(0.0, rj.x, rj.y, -(w2 * ls.psi[2] + alpha * ls.psi[1]));
    (force, moment)
}
