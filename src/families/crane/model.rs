//! Level-luffing four-bar jib crane with a straight jib (thesis `003`, portal cranes).
//!
//! The boom AD turns about the boom-foot pin A; the straight jib C–D–E hangs on the boom head
//! D; the tie EB holds the jib tail E to a fixed pin B. While the boom luffs, the jib head C
//! (and the load) should move almost horizontally. This module is the pure geometry: step 1
//! (boom and jib lengths from the boom and jib angles at the two extreme reaches), step 2
//! (the three design positions, the tie pin B as circumcentre of E1 E2 E3) and the jib-head
//! path with its height variation Δh. No design variables, no I/O.
//!
//! Frame: A = (0, 0), reach runs along −x, y up. Boom D(φ) = (−L_c cos φ, L_c sin φ). The
//! jib tail is E = D + k2 (D − C) with |DE| = a = k2·L_v, |DC| = L_v.

use crate::geom::{circle_circle, cross, link_slider, Side, P2};
use crate::numeric::{interval_peak_with, SearchError};
use std::f64::consts::FRAC_PI_2;

/// Why a crane geometry cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CraneGeomError {
    /// The step-1 angles give no positive jib/boom ratio k (the jib head cannot be at equal
    /// heights at the two extreme reaches).
    #[error("the angles give no positive jib/boom ratio: k = {k}")]
    NoJibRatio { k: f64 },
    /// No positive jib/boom ratio puts the load on the inclined rope at equal heights at both
    /// extreme reaches ([`Boom::levelled`]).
    #[error(
        "no positive jib/boom ratio levels the load: at these angles the jib head would have to rise between maximum and \
         minimum reach by the rope's run-out per fall, about {run_out:.3} m for the level head's jib, and no jib does it"
    )]
    NoLevelJib { run_out: f64 },
    /// The middle design position D2 does not exist: the circle (C2, L_v) misses the boom
    /// circle (A, L_c) on the branch between the extreme boom angles.
    #[error("no middle boom position D2 between phi_min and phi_max for C2 = ({x:.6}, {y:.6})")]
    NoMiddlePosition { x: f64, y: f64 },
    /// A length or ratio is not finite and positive.
    #[error("invalid {what}: {value}")]
    Invalid { what: &'static str, value: f64 },
}

/// The step-1 angles (rad). φ_min: boom elevation at maximum reach; γ1: boom from vertical at
/// minimum reach (φ_max = π/2 − γ1); γ2: jib from vertical at minimum reach; γ3: jib below
/// horizontal at maximum reach.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Angles {
    /// φ_min (rad).
    pub phi_min: f64,
    /// γ1 (rad).
    pub gamma1: f64,
    /// γ2 (rad).
    pub gamma2: f64,
    /// γ3 (rad).
    pub gamma3: f64,
}

impl Angles {
    /// φ_max = π/2 − γ1.
    pub fn phi_max(&self) -> f64 {
        FRAC_PI_2 - self.gamma1
    }

    /// Jib/boom ratio k = L_v/L_c that puts the jib head at equal heights at both extremes
    /// (thesis eqs. 2.1–2.5): k = (cos γ1 − sin φ_min)/(cos γ2 − sin γ3).
    ///
    /// Both differences are evaluated in product form, cos x − sin y =
    /// 2 sin((π/2 − y + x)/2) sin((π/2 − y − x)/2), which keeps its digits when φ_max ≈ φ_min
    /// or γ2 + γ3 ≈ π/2. `None` unless k is finite and positive.
    pub fn k(&self) -> Option<f64> {
        let diff = |x: f64, y: f64| {
            2.0 * ((FRAC_PI_2 - y + x) / 2.0).sin() * ((FRAC_PI_2 - y - x) / 2.0).sin()
        };
        let k = diff(self.gamma1, self.phi_min) / diff(self.gamma2, self.gamma3);
        (k.is_finite() && k > 0.0).then_some(k)
    }

    /// Reach of the jib head from A at maximum reach per metre of boom: cos φ_min + k cos γ3.
    pub fn unit_reach_max(&self, k: f64) -> f64 {
        self.phi_min.cos() + k * self.gamma3.cos()
    }

    /// Reach from A at minimum reach per metre of boom: sin γ1 + k sin γ2.
    pub fn unit_reach_min(&self, k: f64) -> f64 {
        self.gamma1.sin() + k * self.gamma2.sin()
    }

    /// Head height above A at the extremes per metre of boom: sin φ_min − k sin γ3
    /// (= cos γ1 − k cos γ2 by the choice of k).
    pub fn unit_head_height(&self, k: f64) -> f64 {
        self.phi_min.sin() - k * self.gamma3.sin()
    }
}

/// Boom position D(φ) = (−L_c cos φ, L_c sin φ).
pub fn boom_head(l_c: f64, phi: f64) -> P2 {
    P2::new(-l_c * phi.cos(), l_c * phi.sin())
}

/// An inclined hoist rope (thesis §2.2, Fig 2.3): from a fixed sheave S on the frame over
/// the jib-head sheave C down to the load in `parts` falls. The rope's length is constant,
/// so the load hangs at y_L = y_C − (L_r − |S − C|)/n below the head, and the jib head
/// carries the load's weight W downwards plus the lead rope's pull W/n towards S.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HoistRope {
    /// S, the fixed sheave the rope comes from (m, frame of A).
    pub sheave: P2,
    /// n, the falls between the jib head and the load (≥ 1).
    pub parts: f64,
}

impl HoistRope {
    /// The load's height up to a constant: y_C + |S − C|/n (m).
    pub fn load_height(&self, c: P2) -> f64 {
        c.y + (self.sheave - c).norm() / self.parts
    }
}

/// What the three precision points of the synthesis put level: the jib head (thesis §2.1,
/// the hoist rope parallel to the boom or the tie, so the load keeps its distance below the
/// head) or the load on an inclined rope (§2.2, Fig 2.3), whose hanging length changes by the
/// rope's run-out over the jib-head sheave.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "level")]
pub enum Level {
    /// y_C, the jib head's height.
    #[default]
    Head,
    /// y_L = y_C + |S − C|/n up to a constant, the load's height on the rope.
    Load(HoistRope),
}

impl Level {
    /// The levelled height at the jib head `c` (m, up to a constant for the load).
    pub fn height(&self, c: P2) -> f64 {
        match self {
            Level::Head => c.y,
            Level::Load(rope) => rope.load_height(c),
        }
    }

    /// ∂height/∂C: (0, 1) for the head, (0, 1) + (C − S)/(n|C − S|) for the load.
    pub fn gradient(&self, c: P2) -> P2 {
        match self {
            Level::Head => P2::new(0.0, 1.0),
            Level::Load(rope) => {
                let r = c - rope.sheave;
                P2::new(0.0, 1.0) + r / (rope.parts * r.norm())
            }
        }
    }

    /// Bound on |∂height/∂C|: 1 for the head, 1 + 1/n for the load (what a head moved by δ
    /// moves the height by at most, times |δ|).
    pub fn gain(&self) -> f64 {
        match self {
            Level::Head => 1.0,
            Level::Load(rope) => 1.0 + 1.0 / rope.parts,
        }
    }

    /// Length scale the height adds to a pose's rounding: |S|/n for the load (its rope term
    /// |S − C|/n is rounded relative to |S| + |C|), 0 for the head.
    pub fn length_scale(&self) -> f64 {
        match self {
            Level::Head => 0.0,
            Level::Load(rope) => rope.sheave.norm() / rope.parts,
        }
    }
}

/// Step 1 resolved: boom length L_c, jib length L_v = k·L_c and the angles.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Boom {
    /// Boom length L_c (m).
    pub l_c: f64,
    /// Jib/boom ratio k = L_v/L_c.
    pub k: f64,
    /// The step-1 angles.
    pub angles: Angles,
    /// What the precision points put level (the head unless built by [`Boom::levelled`]).
    pub level: Level,
}

impl Boom {
    /// Build from the boom length and the angles (k from [`Angles::k`]): the head level.
    pub fn new(l_c: f64, angles: Angles) -> Result<Boom, CraneGeomError> {
        if !(l_c.is_finite() && l_c > 0.0) {
            return Err(CraneGeomError::Invalid {
                what: "boom length",
                value: l_c,
            });
        }
        let k = angles.k().ok_or_else(|| {
            let raw = (angles.gamma1.cos() - angles.phi_min.sin())
                / (angles.gamma2.cos() - angles.gamma3.sin());
            CraneGeomError::NoJibRatio {
                k: if raw.is_finite() { raw } else { 0.0 },
            }
        })?;
        Ok(Boom {
            l_c,
            k,
            angles,
            level: Level::Head,
        })
    }

    /// Build with the extremes' `level` heights equal: for [`Level::Load`] the thesis's
    /// inclined-rope step 1 (§2.2), the jib head at minimum reach higher than at maximum
    /// reach by h3 = (|S − C1| − |S − C3|)/n, the rope's run-out over the head sheave shared
    /// by its n falls. k solves f(k) = y_L(C3(k)) − y_L(C1(k)) = 0 with
    /// C1(k) = D1 + k L_c(−cos γ3, −sin γ3), C3(k) = D3 + k L_c(−sin γ2, −cos γ2), by
    /// Newton from the head's closed-form k (f'(k) from [`Level::gradient`]), else by a
    /// safeguarded Newton on the first bracket found on k·2^(j/2), j = −40..8 (k/2²⁰ to 16k).
    pub fn levelled(l_c: f64, angles: Angles, level: Level) -> Result<Boom, CraneGeomError> {
        let head = Boom::new(l_c, angles)?;
        if level == Level::Head {
            return Ok(head);
        }
        let (g2, g3) = (angles.gamma2, angles.gamma3);
        let (d1, d3) = (
            boom_head(l_c, angles.phi_min),
            boom_head(l_c, angles.phi_max()),
        );
        let (u1, u3) = (
            l_c * P2::new(-g3.cos(), -g3.sin()),
            l_c * P2::new(-g2.sin(), -g2.cos()),
        );
        let f = |k: f64| {
            let (c1, c3) = (d1 + k * u1, d3 + k * u3);
            (
                level.height(c3) - level.height(c1),
                level.gradient(c3).dot(&u3) - level.gradient(c1).dot(&u1),
            )
        };
        let k0 = head.k;
        let tol = 1e-15 * k0;
        let root = crate::numeric::newton_polish(f, k0, 0.0, 16.0 * k0, tol, 40)
            .map(|r| r.x)
            .or_else(|| {
                let ks: Vec<f64> = (-40..=8).map(|j| k0 * 2f64.powf(j as f64 / 2.0)).collect();
                ks.windows(2)
                    .find(|w| f(w[0]).0 * f(w[1]).0 <= 0.0)
                    .and_then(|w| crate::numeric::newton_root(f, w[0], w[1], tol).ok())
                    .map(|r| r.x)
            });
        match root {
            Some(k) if k.is_finite() && k > 0.0 => Ok(Boom {
                l_c,
                k,
                angles,
                level,
            }),
            _ => {
                let run_out =
                    level.height(head.c1()) - head.c1().y - (level.height(head.c3()) - head.c3().y);
                Err(CraneGeomError::NoLevelJib { run_out })
            }
        }
    }

    /// Jib head length L_v = k·L_c.
    pub fn l_v(&self) -> f64 {
        self.k * self.l_c
    }

    /// C1, the jib head at maximum reach: D(φ_min) + L_v(−cos γ3, −sin γ3).
    pub fn c1(&self) -> P2 {
        let g = self.angles.gamma3;
        boom_head(self.l_c, self.angles.phi_min) + self.l_v() * P2::new(-g.cos(), -g.sin())
    }

    /// C3, the jib head at minimum reach: D(φ_max) + L_v(−sin γ2, −cos γ2).
    pub fn c3(&self) -> P2 {
        let g = self.angles.gamma2;
        boom_head(self.l_c, self.angles.phi_max()) + self.l_v() * P2::new(-g.sin(), -g.cos())
    }

    /// Head height above A at the extremes, H1 = L_c(sin φ_min − k sin γ3) (equal at both
    /// for the head level; for the load level the lower of y_C1 = H1 and y_C3 = H1 + h3).
    pub fn head_height(&self) -> f64 {
        let h1 = self.l_c * self.angles.unit_head_height(self.k);
        match self.level {
            Level::Head => h1,
            Level::Load(_) => h1.min(self.c3().y),
        }
    }
}

/// The three design positions of step 2 (index 0 = max reach, 2 = min reach).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignPositions {
    /// Boom angles φ1 = φ_min, φ2, φ3 = φ_max (rad).
    pub phi: [f64; 3],
    /// Jib heads C1, C2, C3.
    pub c: [P2; 3],
    /// Boom heads D1, D2, D3.
    pub d: [P2; 3],
    /// Jib tails E1, E2, E3.
    pub e: [P2; 3],
    /// The nearer extreme position to the middle one (0 for k1 ≤ ½, else 2) and E2 − E_anchor
    /// computed in difference form (accurate to rounding relative to its own length even
    /// when E2 nearly coincides with E1 or E3, where subtracting the points would lose it).
    pub e_step: (usize, P2),
}

/// Step 2 positions for the ratios k1 = C1C2/C1C3 and k2 = a/L_v.
///
/// C2 = (x_C1 + k1(x_C3 − x_C1), H1); D2 = circle(A, L_c) ∩ circle(C2, L_v) on the side of the
/// line A→C where D1 and D3 lie (the same assembly branch of the boom–jib dyad), which must
/// give φ_min ≤ φ2 ≤ φ_max and y_D2 ≥ H1; E_i = D_i + k2(D_i − C_i).
pub fn design_positions(boom: &Boom, k1: f64, k2: f64) -> Result<DesignPositions, CraneGeomError> {
    if !(k1.is_finite() && (0.0..=1.0).contains(&k1)) {
        return Err(CraneGeomError::Invalid {
            what: "k1",
            value: k1,
        });
    }
    if !(k2.is_finite() && k2 > 0.0) {
        return Err(CraneGeomError::Invalid {
            what: "k2",
            value: k2,
        });
    }
    let (c1, c3) = (boom.c1(), boom.c3());
    let x2 = c1.x + k1 * (c3.x - c1.x);
    let c2 = P2::new(x2, middle_height(boom, c1, c3, x2, k1)?);
    let (p1, p3) = (boom.angles.phi_min, boom.angles.phi_max());
    let (d1, d3) = (boom_head(boom.l_c, p1), boom_head(boom.l_c, p3));
    // The boom–jib dyad A–D–C must stay on one assembly branch: D on the same side of the
    // line A→C at all three positions. (The thesis's "y > H1, x < 0" admits both solutions
    // when C2 is close to C3, and then picks the wrong one.)
    let no_d2 = CraneGeomError::NoMiddlePosition { x: c2.x, y: c2.y };
    let (s1, s3) = (cross(c1, d1), cross(c3, d3));
    if s1.is_nan() || s3.is_nan() || s1 * s3 <= 0.0 {
        return Err(no_d2);
    }
    let side = if s1 > 0.0 { Side::Left } else { Side::Right };
    let d2 = circle_circle(P2::zeros(), boom.l_c, c2, boom.l_v(), side).ok_or(no_d2.clone())?;
    let phi2 = d2.y.atan2(-d2.x);
    let tol = 1e-9 * (p3 - p1).abs().max(1.0);
    if !(phi2 >= p1 - tol && phi2 <= p3 + tol && d2.y >= c2.y) {
        return Err(no_d2);
    }
    // D2 again in difference form from the nearer extreme position a: with w = D_a − C_a
    // (= L_v(cos γ3, sin γ3) at a = 1, L_v(sin γ2, cos γ2) at a = 3), ΔC = C2 − C_a and
    // ΔD(δ) = D(φ_a + δ) − D(φ_a) = 2 L_c sin(δ/2)(sin(φ_a + δ/2), cos(φ_a + δ/2)), the angle
    // δ = φ2 − φ_a solves f(δ) = 2 w·(ΔD − ΔC) + |ΔD − ΔC|² = 0 (|D2 − C2| = L_v) by Newton
    // from the rounded φ2. Every term is relative to |ΔC|, so δ keeps its digits when C2 is
    // within rounding of C1 or C3 (k1 near 0 or 1).
    // ΔC's height is 0 for the head level (C2 on the line y = H1, exact by construction).
    let (g2, g3) = (boom.angles.gamma2, boom.angles.gamma3);
    let rise = |ca: P2| match boom.level {
        Level::Head => 0.0,
        Level::Load(_) => c2.y - ca.y,
    };
    let (a, pa, w, dc) = if k1 <= 0.5 {
        (
            0,
            p1,
            boom.l_v() * P2::new(g3.cos(), g3.sin()),
            P2::new(k1 * (c3.x - c1.x), rise(c1)),
        )
    } else {
        (
            2,
            p3,
            boom.l_v() * P2::new(g2.sin(), g2.cos()),
            P2::new((1.0 - k1) * (c1.x - c3.x), rise(c3)),
        )
    };
    let dd = |del: f64| {
        let h = 0.5 * del;
        2.0 * boom.l_c * h.sin() * P2::new((pa + h).sin(), (pa + h).cos())
    };
    let mut del = phi2 - pa;
    for _ in 0..6 {
        let r = dd(del) - dc;
        let f = 2.0 * w.dot(&r) + r.dot(&r);
        let fp = 2.0 * (w + r).dot(&(boom.l_c * P2::new((pa + del).sin(), (pa + del).cos())));
        let step = f / fp;
        if !step.is_finite() {
            break;
        }
        del -= step;
        if step.abs() <= 1e-17 * del.abs() {
            break;
        }
    }
    let (d2, phi2, dd2) = if del.is_finite() && (pa + del - phi2).abs() <= 1e-6 {
        let dd2 = dd(del);
        ([d1, d2, d3][a] + dd2, pa + del, dd2)
    } else {
        (d2, phi2, d2 - [d1, d2, d3][a])
    };
    let phi2 = phi2.clamp(p1, p3);
    let d = [d1, d2, d3];
    let c = [c1, c2, c3];
    let e = [0, 1, 2].map(|i| d[i] + k2 * (d[i] - c[i]));
    Ok(DesignPositions {
        phi: [p1, phi2, p3],
        c,
        d,
        e,
        e_step: (a, (1.0 + k2) * dd2 - k2 * dc),
    })
}

/// The middle precision point's height y_C2 at x_C2 = `x2` between the extremes C1, C3: H1
/// for the head level; for the
/// load level the root of y_L(x2, y) = y_L(C1), i.e. y_C2 = H1 + h2 with the thesis's
/// h2 = (|S − C1| − |S − C2|)/n. y_L is convex and non-decreasing in y (∂y_L/∂y =
/// 1 − (y_S − y)/(n|S − C|) ≥ 1 − 1/n), so Newton from the chord's height
/// y_C1 + k1(y_C3 − y_C1) converges; a rope of one fall directly above the head (∂y_L/∂y = 0)
/// has no such point and is [`CraneGeomError::NoMiddlePosition`].
fn middle_height(boom: &Boom, c1: P2, c3: P2, x2: f64, k1: f64) -> Result<f64, CraneGeomError> {
    if boom.level == Level::Head {
        return Ok(c1.y);
    }
    let target = boom.level.height(c1);
    let g = |y: f64| {
        let c = P2::new(x2, y);
        (boom.level.height(c) - target, boom.level.gradient(c).y)
    };
    let y0 = c1.y + k1 * (c3.y - c1.y);
    let span = boom.l_c;
    crate::numeric::newton_polish(g, y0, y0 - span, y0 + span, 1e-15 * span, 60)
        .or_else(|| crate::numeric::newton_root(g, y0 - span, y0 + span, 1e-15 * span).ok())
        .map(|r| r.x)
        .filter(|y| y.is_finite())
        .ok_or(CraneGeomError::NoMiddlePosition { x: x2, y: y0 })
}

/// What guides the jib tail E: the tie (a circle about the tie pin B) or, in the limit of
/// collinear E1 E2 E3 (B at infinity), a straight line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Guide {
    /// Tie of length `radius` about the pin `centre`.
    Circle { centre: P2, radius: f64 },
    /// Straight guide through `point` with unit direction `dir` (the infinite-tie limit).
    Line { point: P2, dir: P2 },
}

/// Which assembly branch each design position is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    /// All three positions on the same branch (`side` of [`circle_circle`] from D towards B,
    /// or of [`link_slider`] along the guide).
    Consistent(Side),
    /// The positions are on different branches: the linkage cannot move through all three
    /// without being taken apart. `None` marks a position at a singular (tangent) pose.
    Defect([Option<Side>; 3]),
}

/// Ratio of tie length to the chord E1E3 beyond which the circle is replaced by its
/// straight-line limit: the rounding of the circle intersection (≈ ε·b) then exceeds the
/// sagitta of the replaced arc (chord²/(8b)); the crossover is b ≈ chord/sqrt(8ε) ≈ 2.4e7·chord.
pub const LINE_LIMIT_RATIO: f64 = 2.4e7;

/// The four-bar linkage after step 2: boom, jib tail and the guide of the tail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linkage {
    /// Boom length L_c (m).
    pub l_c: f64,
    /// Jib tail a = k2·L_v (m).
    pub a: f64,
    /// k2 = a/L_v.
    pub k2: f64,
    /// Tie or straight guide.
    pub guide: Guide,
    /// Assembly branch followed (continuous in φ while the linkage assembles).
    pub side: Side,
    /// Luffing range [φ_min, φ_max] (rad).
    pub phi_range: [f64; 2],
}

/// A pose of the linkage at boom angle φ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Boom head D.
    pub d: P2,
    /// Jib tail E.
    pub e: P2,
    /// Jib head C = D + (D − E)/k2.
    pub c: P2,
}

/// Step 2 completed: the positions, the guide, the branch and the linkage to follow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Synthesis {
    /// The three design positions.
    pub positions: DesignPositions,
    /// Tie about the circumcentre of E1 E2 E3, or its line limit.
    pub guide: Guide,
    /// Bound on the rounding error of the tie pin B and of the tie length (m): see
    /// [`tie_circle`].
    pub guide_error: f64,
    /// Smallest angle of the triangle E1 E2 E3 (rad; 0 when two points coincide).
    pub min_angle: f64,
    /// Branch of each design position.
    pub branch: Branch,
    /// The linkage on the branch of position 1 (the max-reach position).
    pub linkage: Linkage,
}

/// Side of the guide on which E lies as seen from D: sign of (B − D) × (E − D) for a tie,
/// of (E − foot)·u for a line. `None` within rounding of the singular (tangent) pose.
fn side_of(guide: &Guide, d: P2, e: P2, a: f64) -> Option<Side> {
    let (s, scale) = match *guide {
        Guide::Circle { centre, .. } => (cross(centre - d, e - d), (centre - d).norm() * a),
        Guide::Line { point, dir } => ((e - point).dot(&dir) - (d - point).dot(&dir), a),
    };
    if s.abs() <= 1e-9 * scale {
        None
    } else if s > 0.0 {
        Some(Side::Left)
    } else {
        Some(Side::Right)
    }
}

/// The circle through E1 E2 E3 as [`tie_circle`] computes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TieCircle {
    /// Centre B and radius b, `None` for collinear points.
    pub circle: Option<(P2, f64)>,
    /// Bound on the rounding error of B and b (m).
    pub error: f64,
    /// Longest side of the triangle (m).
    pub longest: f64,
    /// Smallest angle of the triangle (rad).
    pub min_angle: f64,
}

/// Circumcentre of E1 E2 E3, anchored at the vertex of the largest angle A (opposite the
/// longest side), from the sides in difference form (E2 − E_anchor of
/// [`DesignPositions::e_step`], the other side by E3 − E1): with u, v the sides from that
/// vertex, B = vertex + (v_y|u|² − u_y|v|², u_x|v|² − v_x|u|²)/(2 u×v). The whole triangle
/// decides collinearity: the points are collinear only when A is within rounding of π
/// (sin A = 0); two nearly coinciding points with a finite circle (A well below π, the
/// smallest angle near 0) keep their circle. Rounding: u×v carries a relative error of
/// ~ε/sin A, so |δB| ≤ 16ε(|B − vertex|/sin A + |vertex| + longest side) — the condition
/// estimate 1/sin A times ε times the scale.
pub fn tie_circle(pos: &DesignPositions) -> TieCircle {
    let [e1, e2, e3] = pos.e;
    let (a, step) = pos.e_step;
    let v13 = e3 - e1;
    let (v12, v23) = if a == 0 {
        (step, v13 - step)
    } else {
        (v13 + step, -step)
    };
    let (l12, l23, l13) = (v12.norm(), v23.norm(), v13.norm());
    let longest = l12.max(l23).max(l13);
    // Vertex of the largest angle and the sides from it.
    let (vertex, u, v) = if l13 >= l12 && l13 >= l23 {
        (e2, -v12, v23)
    } else if l12 >= l23 {
        (e3, -v13, -v23)
    } else {
        (e1, v12, v13)
    };
    let (uu, vv) = (u.norm_squared(), v.norm_squared());
    let cr = cross(u, v);
    let sin_a = cr.abs() / (uu * vv).sqrt();
    // The smallest angle is opposite the shortest side: sin = 2·area/(product of the others).
    let shortest = l12.min(l23).min(l13);
    let min_angle = if longest > 0.0 {
        (cr.abs() / (longest * (l12 + l23 + l13 - longest - shortest)))
            .min(1.0)
            .asin()
    } else {
        0.0
    };
    if !(sin_a > 0.0) || !sin_a.is_finite() {
        return TieCircle {
            circle: None,
            error: f64::INFINITY,
            longest,
            min_angle,
        };
    }
    let o = P2::new(v.y * uu - u.y * vv, u.x * vv - v.x * uu) / (2.0 * cr);
    let r = o.norm();
    TieCircle {
        circle: Some((vertex + o, r)),
        error: 16.0 * f64::EPSILON * (r / sin_a + vertex.norm() + longest),
        longest,
        min_angle,
    }
}

/// Step 2: tie pin B = circumcentre of E1 E2 E3, tie length b = |BE1|, and the branch of each
/// design position. Collinear E points (or a tie longer than [`LINE_LIMIT_RATIO`] chords) give
/// the straight-guide limit through E1 and E3.
pub fn synthesize(boom: &Boom, k1: f64, k2: f64) -> Result<Synthesis, CraneGeomError> {
    let positions = design_positions(boom, k1, k2)?;
    let [e1, _, e3] = positions.e;
    let chord = (e3 - e1).norm();
    let tc = tie_circle(&positions);
    let (guide, guide_error) = match tc.circle {
        Some((centre, radius)) if radius <= LINE_LIMIT_RATIO * tc.longest => {
            (Guide::Circle { centre, radius }, tc.error)
        }
        // The line limit departs from the circle (radius b, if the points are not exactly
        // collinear) by at most its sagitta over the tail's travel, ~longest²/(8b); twice that
        // is carried as the guide's error.
        circle => (
            Guide::Line {
                point: e1,
                dir: (e3 - e1) / chord,
            },
            circle.map_or(0.0, |(_, b)| tc.longest * tc.longest / (4.0 * b)),
        ),
    };
    let a = k2 * boom.l_v();
    let sides = [0, 1, 2].map(|i| side_of(&guide, positions.d[i], positions.e[i], a));
    let known: Vec<Side> = sides.iter().flatten().copied().collect();
    let branch = match known.first() {
        None => Branch::Consistent(Side::Left),
        Some(&s0) if known.iter().all(|&s| s == s0) => Branch::Consistent(s0),
        Some(_) => Branch::Defect(sides),
    };
    let side = match branch {
        Branch::Consistent(s) => s,
        Branch::Defect(_) => sides[0].or(sides[2]).unwrap_or(Side::Left),
    };
    let linkage = Linkage {
        l_c: boom.l_c,
        a,
        k2,
        guide,
        side,
        phi_range: [positions.phi[0], positions.phi[2]],
    };
    Ok(Synthesis {
        positions,
        guide,
        guide_error,
        min_angle: tc.min_angle,
        branch,
        linkage,
    })
}

impl Linkage {
    /// Pose at boom angle φ: E = circle(D, a) ∩ circle(B, b) (or the line guide) on the
    /// linkage's fixed side, C = D + (D − E)/k2. `None` where the linkage cannot assemble.
    pub fn pose(&self, phi: f64) -> Option<Pose> {
        let d = boom_head(self.l_c, phi);
        let e = match self.guide {
            Guide::Circle { centre, radius } => {
                circle_circle(d, self.a, centre, radius, self.side)?
            }
            Guide::Line { point, dir } => link_slider(d, self.a, point, dir, self.side)?,
        };
        Some(Pose {
            d,
            e,
            c: d + (d - e) / self.k2,
        })
    }

    /// Transmission quality at a pose: the angle μ between the tie force line at E (E→B, or
    /// the guide normal for a line) and the jib tail E→D, folded to min(μ, π − μ) ∈ [0, π/2].
    /// 0 is the singular pose (tie and tail aligned), π/2 the best.
    pub fn transmission_angle(&self, pose: &Pose) -> f64 {
        let f = match self.guide {
            Guide::Circle { centre, .. } => centre - pose.e,
            Guide::Line { dir, .. } => P2::new(-dir.y, dir.x),
        };
        let t = pose.d - pose.e;
        let mu = cross(f, t).abs().atan2(f.dot(&t));
        mu.min(std::f64::consts::PI - mu)
    }

    /// Scale of the lengths that enter a pose, for rounding estimates (m).
    pub fn length_scale(&self) -> f64 {
        let g = match self.guide {
            Guide::Circle { centre, radius } => centre.norm() + radius,
            Guide::Line { point, .. } => point.norm(),
        };
        self.l_c + self.a + g
    }
}

/// The jib-head height over the luffing range with refined extrema.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HeadHeights {
    /// Highest head position y_C,max (m above A) and its boom angle (rad).
    pub y_max: f64,
    /// Boom angle of the highest position (rad).
    pub phi_at_max: f64,
    /// Lowest head position y_C,min (m above A).
    pub y_min: f64,
    /// Boom angle of the lowest position (rad).
    pub phi_at_min: f64,
    /// Δh = y_C,max − y_C,min (m).
    pub delta_h: f64,
    /// Estimated absolute error of Δh (m): refinement ½|y''|xtol² at both extrema plus
    /// rounding 64 ε·(length scale)/k2 (the head is extrapolated from D and E by 1/k2).
    pub error: f64,
    /// Smallest transmission angle seen on the samples (rad, see
    /// [`Linkage::transmission_angle`]).
    pub min_transmission: f64,
    /// Boom angle of the smallest transmission angle (rad).
    pub phi_at_min_transmission: f64,
    /// Pose evaluations spent.
    pub evals: usize,
}

/// Why the head path could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// The linkage does not assemble at this boom angle on its branch.
    #[error("the linkage cannot assemble at phi = {phi} rad")]
    CannotAssemble { phi: f64 },
    /// The refinement failed.
    #[error("refinement failed: {0}")]
    Search(#[from] SearchError),
}

/// Head heights over [φ_min, φ_max]: `n` samples (every one must assemble, so the path
/// follows one branch continuously between them), each sampled local extremum of y_C refined
/// by Brent to `xtol` rad with [`crate::numeric::interval_peak`].
pub fn head_heights(link: &Linkage, n: usize, xtol: f64) -> Result<HeadHeights, PathError> {
    head_heights_with(link, n, Some(xtol))
}

/// [`head_heights`] with `Some(xtol)`; with `None` the sampled extrema are not refined (each
/// is low by at most |y_C''|h²/8, h = (φ_max − φ_min)/n, which the `error` then carries).
pub fn head_heights_with(
    link: &Linkage,
    n: usize,
    xtol: Option<f64>,
) -> Result<HeadHeights, PathError> {
    level_heights_with(link, &Level::Head, n, xtol)
}

/// [`head_heights_with`] for the height `level` measures: the jib head's, or the load's on an
/// inclined rope ([`Level::Load`]); every field then describes that height (y_max, Δh, …).
pub fn level_heights_with(
    link: &Linkage,
    level: &Level,
    n: usize,
    xtol: Option<f64>,
) -> Result<HeadHeights, PathError> {
    let [p0, p1] = link.phi_range;
    let n = n.max(8);
    let mut min_t = f64::INFINITY;
    let mut phi_t = p0;
    for i in 0..=n {
        let phi = p0 + (p1 - p0) * i as f64 / n as f64;
        let pose = link.pose(phi).ok_or(PathError::CannotAssemble { phi })?;
        let t = link.transmission_angle(&pose);
        if t < min_t {
            min_t = t;
            phi_t = phi;
        }
    }
    // A pose that fails between samples (a gap narrower than the spacing) shows up as NaN
    // here and is reported by interval_peak as not finite.
    let y = |phi: f64| link.pose(phi).map_or(f64::NAN, |p| level.height(p.c));
    let to_path = |e: SearchError| match e {
        SearchError::NotFinite { x } => PathError::CannotAssemble { phi: x },
        other => PathError::Search(other),
    };
    let hi = interval_peak_with(y, p0, p1, n, xtol).map_err(to_path)?;
    let lo = interval_peak_with(|phi| -y(phi), p0, p1, n, xtol).map_err(to_path)?;
    // A pose within μ of the singular (tangent) one loses digits as 1/sin μ (the circle
    // intersection's height over its rounding), at most to sqrt(ε).
    let tangency = min_t.sin().max(f64::EPSILON.sqrt());
    let rounding = 64.0 * f64::EPSILON * link.length_scale() / (link.k2 * tangency)
        + 64.0 * f64::EPSILON * level.length_scale();
    Ok(HeadHeights {
        y_max: hi.peak.fx,
        phi_at_max: hi.peak.x,
        y_min: -lo.peak.fx,
        phi_at_min: lo.peak.x,
        delta_h: hi.peak.fx + lo.peak.fx,
        error: hi.error + lo.error + rounding,
        min_transmission: min_t,
        phi_at_min_transmission: phi_t,
        evals: n + 1 + hi.evals + lo.evals,
    })
}

/// A local extremum of the head height: boom angle φ (rad), y_C (m above A), maximum or minimum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalExtremum {
    /// Boom angle (rad).
    pub phi: f64,
    /// Head height y_C (m above A).
    pub y: f64,
    /// A maximum (`false`: a minimum).
    pub is_max: bool,
}

/// Every local extremum of y_C over [φ_min, φ_max], ends included: `n` samples (every one
/// must assemble), each sampled local maximum (minimum) refined by Brent to `xtol` rad on
/// its two neighbouring intervals. The largest maximum minus the smallest minimum is Δh; the
/// others are the pieces a local search must watch, since they can take over.
pub fn head_extrema(link: &Linkage, n: usize, xtol: f64) -> Result<Vec<LocalExtremum>, PathError> {
    level_extrema(link, &Level::Head, n, xtol)
}

/// [`head_extrema`] of the height `level` measures (the head's or the load's); `y` is that
/// height.
pub fn level_extrema(
    link: &Linkage,
    level: &Level,
    n: usize,
    xtol: f64,
) -> Result<Vec<LocalExtremum>, PathError> {
    let [p0, p1] = link.phi_range;
    let n = n.max(8);
    let phi = |i: usize| p0 + (p1 - p0) * i as f64 / n as f64;
    let ys = (0..=n)
        .map(|i| {
            let p = phi(i);
            link.pose(p)
                .map(|q| level.height(q.c))
                .ok_or(PathError::CannotAssemble { phi: p })
        })
        .collect::<Result<Vec<f64>, _>>()?;
    let y = |p: f64| link.pose(p).map_or(f64::NAN, |q| level.height(q.c));
    let to_path = |e: SearchError| match e {
        SearchError::NotFinite { x } => PathError::CannotAssemble { phi: x },
        other => PathError::Search(other),
    };
    let mut out = Vec::new();
    for i in 0..=n {
        let (l, r) = (i.saturating_sub(1), (i + 1).min(n));
        for sign in [1.0, -1.0] {
            let s = |j: usize| sign * ys[j];
            if s(i) >= s(l) && s(i) >= s(r) && (i == 0 || s(i) > s(l)) {
                let e = crate::numeric::brent_max(|p| sign * y(p), phi(l), phi(r), xtol)
                    .map_err(to_path)?;
                // An extremum at an end of the range is the end sample itself: Brent would
                // stop up to xtol inside it and lose |y'|·xtol.
                let (phi_e, fx) = if s(i) > e.fx {
                    (phi(i), s(i))
                } else {
                    (e.x, e.fx)
                };
                out.push(LocalExtremum {
                    phi: phi_e,
                    y: sign * fx,
                    is_max: sign > 0.0,
                });
            }
        }
    }
    Ok(out)
}

/// Unbalanced moment of a load of weight W hanging from the jib head on a rope of constant
/// length (hoist rope parallel to boom or tie, thesis §2.1) about A, by virtual work
/// M_A(φ) = W·dy_C/dφ. dy_C/dφ by the fourth-order central difference
/// (8(y(φ+h) − y(φ−h)) − (y(φ+2h) − y(φ−2h)))/(12h); within 2h of an end of the range the
/// stencil centre is moved inside. Returns (M, error), the error being the change from the
/// second-order difference, plus, for a moved centre c, twice the Taylor estimate of
/// |M(φ) − M(c)| ≤ W(|c − φ|·|y''| + ½(c − φ)²|y'''|) (the differences of y at c), and
/// rounding. `None` if a pose fails.
pub fn load_moment(link: &Linkage, weight: f64, phi: f64, h: f64) -> Option<(f64, f64)> {
    level_load_moment(link, &Level::Head, weight, phi, h)
}

/// [`load_moment`] of a load whose height `level` gives: M_A = W·dy_L/dφ with y_L the
/// head's height, or the load's on an inclined rope ([`Level::Load`], whose pull on the head
/// the virtual work includes).
pub fn level_load_moment(
    link: &Linkage,
    level: &Level,
    weight: f64,
    phi: f64,
    h: f64,
) -> Option<(f64, f64)> {
    let [p0, p1] = link.phi_range;
    let h = h.min((p1 - p0) / 8.0);
    let c = phi.clamp(p0 + 2.0 * h, p1 - 2.0 * h);
    let y = |p: f64| link.pose(p).map(|q| level.height(q.c));
    let (ym2, ym1, y0, yp1, yp2) = (
        y(c - 2.0 * h)?,
        y(c - h)?,
        y(c)?,
        y(c + h)?,
        y(c + 2.0 * h)?,
    );
    let d2nd = (yp1 - ym1) / (2.0 * h);
    let d4th = (8.0 * (yp1 - ym1) - (yp2 - ym2)) / (12.0 * h);
    let curv = (yp1 - 2.0 * y0 + ym1) / (h * h);
    let third = (yp2 - 2.0 * yp1 + 2.0 * ym1 - ym2) / (2.0 * h * h * h);
    let rounding = 64.0 * f64::EPSILON * link.length_scale() / (link.k2 * h * h * h)
        + 64.0 * f64::EPSILON * level.length_scale() / (h * h * h);
    let shift = (c - phi).abs();
    let moved = if shift > 0.0 {
        2.0 * (shift * curv.abs() + 0.5 * shift * shift * (third.abs() + rounding))
    } else {
        0.0
    };
    let err = (d4th - d2nd).abs() + moved + rounding * h * h;
    Some((weight * d4th, weight.abs() * err))
}
