//! Exact area, first moment and polar second moment of a plane region bounded by straight
//! edges and circular arcs (a plate drawn as closed outlines, holes included), so that a body's
//! mass, centroid and inertia come from the drawing a designer already has instead of numbers
//! typed by hand. Reading the drawing is `problem::outline`; this module knows no file.
//!
//! **Green's theorem.** For a region D with counter-clockwise boundary ∂D and a function f
//! homogeneous of degree k (f(λp) = λᵏ f(p)),
//!
//! ∫∫_D f dA = 1/(k + 2) ∮_∂D f(p) (x dy − y dx),
//!
//! so A = ½∮(x dy − y dx) (f = 1), S = ∫∫ p dA = ⅓∮ p (x dy − y dx) (f = x, y) and
//! J = ∫∫ (x² + y²) dA = ¼∮ |p|² (x dy − y dx) (f = |p|²). The boundary integral is a sum over
//! the edges, each in closed form:
//!
//! * a **straight edge** a → b (x dy − y dx = (a × b) ds along p = a + s (b − a)), with
//!   w = a × b: A = w/2, S = w (a + b)/6, J = w (|a|² + a·b + |b|²)/12 — the signed triangle
//!   (0, a, b), the textbook polygon formulas;
//! * a **circular arc** of centre c, radius r, signed sweep Δ (> 0 counter-clockwise; a DXF
//!   bulge b is Δ = 4 atan b) from a to b: its chord a → b (above) plus the circular segment
//!   between chord and arc, whose integrals about c are the sector's minus the triangle
//!   (c, a, b)'s, with α = Δ/2 and e the unit vector along the arc's bisector:
//!   A = r² (Δ − sin Δ)/2, S_c = ⅔ r³ sin³α e, J_c = r⁴ (3Δ − sin Δ (2 + cos Δ))/12, moved to
//!   the origin by S = S_c + A c, J = J_c + 2 c·S_c + A |c|². All three are odd in Δ, so a
//!   clockwise arc subtracts; a full circle is the arc from a point back to itself (Δ = 2π:
//!   A = π r², J_c = π r⁴/2). Both differences cancel for a flat arc (they are ~Δ³), so they are
//!   taken as f(Δ) and 2 f(Δ) + f(2Δ)/2 with f(x) = x − sin x by its series ([`x_minus_sin`]):
//!   a far disc's arc in a lens (`plate`) keeps its digits (for an arc bulging 1e-4 R from its
//!   chord in a disc of radius R, Δ ≈ 4e-4, the textbook forms lost 2e-9 relative of the
//!   lens's first moment and 3e-6 of its polar moment; now 4e-16 and 3e-12).
//!
//! **Holes.** Each closed loop is integrated in its own direction and then counted with the
//! sign of its area (orientation does not matter); a loop inside an odd number of other loops
//! is a hole and subtracts, inside an even number (an island in a hole) it adds. Nesting is
//! decided by the winding number of every vertex of one loop about the other, exactly for arcs:
//! an arc turns the view from q by its chord's angle plus 2π·sign Δ when q lies in its circular
//! segment. Loops that cross are refused.
//!
//! The integrals are taken about a point of the drawing (the middle of its bounding box), so
//! the centroidal inertia J − |S|²/A does not cancel away when the part is drawn far from the
//! origin.
//!
//! Hand-written because no crate integrates DXF outlines exactly: polygon crates (`geo`'s
//! area and centroid) take straight edges only — arcs would have to be flattened, which is
//! not exact — and none gives the second moment with holes by nesting.

use super::{cross, dir, perp, P2};

/// A circular arc: centre, radius, start angle and signed sweep (rad; > 0 counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Centre c.
    pub centre: P2,
    /// Radius r > 0.
    pub radius: f64,
    /// Angle of the start point about the centre.
    pub start: f64,
    /// Δ: signed sweep, |Δ| ≤ 2π.
    pub sweep: f64,
}

/// One edge of an outline, from `from` to `to`: straight, or along an arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// Start point.
    pub from: P2,
    /// End point.
    pub to: P2,
    /// The arc it follows (`None`: straight).
    pub arc: Option<Arc>,
}

/// The integrals of a region: A, S = ∫∫ p dA and J = ∫∫ |p|² dA about the origin. For a
/// loop's edges they are signed (counter-clockwise positive).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Moments {
    /// A (length²).
    pub area: f64,
    /// S = (∫∫ x dA, ∫∫ y dA) (length³).
    pub first: P2,
    /// J = ∫∫ (x² + y²) dA (length⁴).
    pub second: f64,
}

impl std::ops::Add for Moments {
    type Output = Moments;
    fn add(self, o: Moments) -> Moments {
        Moments {
            area: self.area + o.area,
            first: self.first + o.first,
            second: self.second + o.second,
        }
    }
}

impl std::ops::Mul<f64> for Moments {
    type Output = Moments;
    fn mul(self, k: f64) -> Moments {
        Moments {
            area: self.area * k,
            first: self.first * k,
            second: self.second * k,
        }
    }
}

impl Moments {
    /// The centroid S/A.
    pub fn centroid(&self) -> P2 {
        self.first / self.area
    }

    /// J about the centroid, J − |S|²/A.
    pub fn second_about_centroid(&self) -> f64 {
        self.second - self.first.norm_squared() / self.area
    }

    /// The same region's integrals with the origin moved to −`v` (the region shifted by `v`):
    /// S + A v, J + 2 v·S + A |v|².
    pub fn shifted(&self, v: P2) -> Moments {
        Moments {
            area: self.area,
            first: self.first + v * self.area,
            second: self.second + 2.0 * v.dot(&self.first) + self.area * v.norm_squared(),
        }
    }
}

impl Edge {
    /// A straight edge.
    pub fn line(from: P2, to: P2) -> Edge {
        Edge {
            from,
            to,
            arc: None,
        }
    }

    /// The arc of centre `centre` and radius `radius` from the angle `start` through the
    /// signed `sweep` (a full circle: `sweep` = ±2π).
    pub fn arc(centre: P2, radius: f64, start: f64, sweep: f64) -> Edge {
        Edge {
            from: centre + dir(start) * radius,
            to: centre + dir(start + sweep) * radius,
            arc: Some(Arc {
                centre,
                radius,
                start,
                sweep,
            }),
        }
    }

    /// The edge from `from` to `to` with the DXF bulge `b` = tan(Δ/4) (0: straight; > 0
    /// counter-clockwise; 1: a half circle). Its centre lies off the chord's midpoint by
    /// (1 − b²)/(4b) times the chord turned by +90°, its radius is |chord| (1 + b²)/(4|b|).
    pub fn bulge(from: P2, to: P2, b: f64) -> Edge {
        let d = to - from;
        if b == 0.0 || d.norm() == 0.0 {
            return Edge::line(from, to);
        }
        let centre = (from + to) / 2.0 + perp(d) * ((1.0 - b * b) / (4.0 * b));
        let r = d.norm() * (1.0 + b * b) / (4.0 * b.abs());
        let a = from - centre;
        Edge {
            from,
            to,
            arc: Some(Arc {
                centre,
                radius: r,
                start: a.y.atan2(a.x),
                sweep: 4.0 * b.atan(),
            }),
        }
    }

    /// The edge walked backwards.
    pub fn reversed(self) -> Edge {
        Edge {
            from: self.to,
            to: self.from,
            arc: self.arc.map(|a| Arc {
                start: a.start + a.sweep,
                sweep: -a.sweep,
                ..a
            }),
        }
    }

    /// The edge mirrored in the y axis, (x, y) → (−x, y) (a DXF entity whose normal is −z).
    pub fn mirrored(self) -> Edge {
        let m = |p: P2| P2::new(-p.x, p.y);
        Edge {
            from: m(self.from),
            to: m(self.to),
            arc: self.arc.map(|a| Arc {
                centre: m(a.centre),
                start: std::f64::consts::PI - a.start,
                sweep: -a.sweep,
                ..a
            }),
        }
    }

    /// The edge moved by `v`.
    pub fn translated(self, v: P2) -> Edge {
        Edge {
            from: self.from + v,
            to: self.to + v,
            arc: self.arc.map(|a| Arc {
                centre: a.centre + v,
                ..a
            }),
        }
    }

    /// The edge scaled by `k` about the origin, moved by `v`, then turned by `psi` about
    /// the origin: p ↦ Rot(ψ)(k p + v) (a drawing's edge put in a body's frame, SI).
    pub fn placed(self, k: f64, v: P2, psi: f64) -> Edge {
        let f = |p: P2| super::rot(psi, p * k + v);
        Edge {
            from: f(self.from),
            to: f(self.to),
            arc: self.arc.map(|a| Arc {
                centre: f(a.centre),
                radius: a.radius * k,
                start: a.start + psi,
                ..a
            }),
        }
    }

    /// Its part of the boundary integrals (module doc): the chord's triangle with the
    /// origin, plus for an arc its circular segment.
    pub fn moments(&self) -> Moments {
        let (a, b) = (self.from, self.to);
        let w = cross(a, b);
        let chord = Moments {
            area: w / 2.0,
            first: (a + b) * (w / 6.0),
            second: w * (a.norm_squared() + a.dot(&b) + b.norm_squared()) / 12.0,
        };
        let Some(arc) = self.arc else {
            return chord;
        };
        let (r, d) = (arc.radius, arc.sweep);
        let f = x_minus_sin(d);
        let half = (d / 2.0).sin();
        let about_centre = Moments {
            area: r * r * f / 2.0,
            first: dir(arc.start + d / 2.0) * (2.0 / 3.0 * r.powi(3) * half.powi(3)),
            // 3Δ − sin Δ (2 + cos Δ) = 2 (Δ − sin Δ) + (2Δ − sin 2Δ)/2: two positive terms.
            second: r.powi(4) * (2.0 * f + x_minus_sin(2.0 * d) / 2.0) / 12.0,
        };
        chord + about_centre.shifted(arc.centre)
    }

    /// The angle through which the view from `q` turns along the edge (q not on it): the
    /// chord's angle, and for an arc 2π·sign Δ more when q lies in its circular segment. A q
    /// on the chord itself (between the ends) is where the arc turns the view by π·sign Δ.
    fn turn(&self, q: P2) -> f64 {
        let (a, b) = (self.from - q, self.to - q);
        let d = self.to - self.from;
        // a × b = d × (q − from), written once so that the chord's angle and the side of the
        // chord q is on never disagree in sign.
        let side = cross(d, q - self.from);
        let chord = side.atan2(a.dot(&b));
        let Some(arc) = self.arc else {
            return chord;
        };
        let pi = std::f64::consts::PI;
        if side == 0.0 && a.dot(&b) < 0.0 {
            return pi * arc.sweep.signum();
        }
        let in_disc = (q - arc.centre).norm() < arc.radius;
        if in_disc && (d == P2::zeros() || side * arc.sweep < 0.0) {
            chord + 2.0 * pi * arc.sweep.signum()
        } else {
            chord
        }
    }
}

/// x − sin x, to full precision also where the difference cancels: its Taylor series
/// Σₖ₌₁ (−1)ᵏ⁺¹ x²ᵏ⁺¹/(2k+1)! for |x| < 2 (13 terms leave < 1e-18 relative), the difference
/// itself beyond (which then loses less than a factor 2).
pub fn x_minus_sin(x: f64) -> f64 {
    if x.abs() >= 2.0 {
        return x - x.sin();
    }
    let x2 = x * x;
    let mut term = x * x2 / 6.0;
    let mut sum = 0.0;
    for k in 1..=13 {
        sum += term;
        let k = f64::from(k);
        term *= -x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    }
    sum
}

/// A closed loop of edges, each starting where the one before ends (within the tolerance
/// it was chained with).
#[derive(Debug, Clone, PartialEq)]
pub struct Loop {
    /// Its edges, in order.
    pub edges: Vec<Edge>,
}

impl Loop {
    /// Its signed integrals (counter-clockwise positive).
    pub fn moments(&self) -> Moments {
        self.edges
            .iter()
            .map(Edge::moments)
            .fold(Moments::default(), |s, m| s + m)
    }

    /// How many times the loop winds about `q` (counter-clockwise positive; `q` not on it).
    pub fn winding(&self, q: P2) -> i64 {
        let turn: f64 = self.edges.iter().map(|e| e.turn(q)).sum();
        (turn / std::f64::consts::TAU).round() as i64
    }
}

/// Why edges do not make closed loops.
#[derive(Debug, Clone, PartialEq)]
pub enum ChainError {
    /// A chain of edges ends at `end` with no edge starting there: the nearest other free end
    /// (if any) and its distance.
    Open {
        /// The open end.
        end: P2,
        /// The nearest end of another edge not yet in a loop, and how far it is.
        nearest: Option<(P2, f64)>,
    },
    /// More than two edge ends meet at `at` (a branch: the loop is ambiguous).
    Branch {
        /// Where.
        at: P2,
    },
}

/// Chains `edges` (in any order and direction) into closed loops: an edge's end meets the
/// next edge's start or end within `tol`. An edge closed on itself (a full circle) is a loop.
pub fn chain(edges: &[Edge], tol: f64) -> Result<Vec<Loop>, ChainError> {
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for s in 0..edges.len() {
        if used[s] {
            continue;
        }
        used[s] = true;
        let start = edges[s].from;
        let mut path = vec![edges[s]];
        loop {
            let end = path.last().expect("a path has an edge").to;
            let closes = (end - start).norm() <= tol;
            let next: Vec<(usize, Edge)> = (0..edges.len())
                .filter(|&j| !used[j])
                .filter_map(|j| {
                    let e = edges[j];
                    if (e.from - end).norm() <= tol {
                        Some((j, e))
                    } else if (e.to - end).norm() <= tol {
                        Some((j, e.reversed()))
                    } else {
                        None
                    }
                })
                .collect();
            match (closes, next.as_slice()) {
                (true, []) => break,
                (false, [(j, e)]) => {
                    used[*j] = true;
                    path.push(*e);
                }
                (false, []) => {
                    let nearest = (0..edges.len())
                        .filter(|&j| !used[j])
                        .flat_map(|j| [edges[j].from, edges[j].to])
                        .chain(std::iter::once(start))
                        .map(|p| (p, (p - end).norm()))
                        .min_by(|a, b| a.1.total_cmp(&b.1));
                    return Err(ChainError::Open { end, nearest });
                }
                _ => return Err(ChainError::Branch { at: end }),
            }
        }
        loops.push(Loop { edges: path });
    }
    Ok(loops)
}

/// Why closed loops do not bound a region.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionError {
    /// Loop `i` encloses no area.
    Empty(usize),
    /// Loops `i` and `j` cross (or touch): some of `i`'s vertices are inside `j`, some not.
    Crossing(usize, usize),
}

/// The integrals of the region the loops bound (module doc: holes by nesting parity), about
/// the point `about` (those of the region moved by −`about`): with `about` in or near the
/// region its centroidal J does not cancel away; `.shifted(about)` gives them about the
/// origin.
pub fn region(loops: &[Loop], about: P2) -> Result<Moments, RegionError> {
    let local: Vec<Loop> = loops
        .iter()
        .map(|l| Loop {
            edges: l.edges.iter().map(|e| e.translated(-about)).collect(),
        })
        .collect();
    let mut total = Moments::default();
    for (i, l) in local.iter().enumerate() {
        let m = l.moments();
        if !(m.area.abs() > 0.0) {
            return Err(RegionError::Empty(i));
        }
        let mut depth = 0;
        for (j, other) in local.iter().enumerate().filter(|&(j, _)| j != i) {
            let inside = l
                .edges
                .iter()
                .filter(|e| other.winding(e.from) != 0)
                .count();
            if inside == l.edges.len() {
                depth += 1;
            } else if inside != 0 {
                return Err(RegionError::Crossing(i, j));
            }
        }
        let parity = if depth % 2 == 0 { 1.0 } else { -1.0 };
        total = total + m * (m.area.signum() * parity);
    }
    Ok(total)
}

/// A plate of uniform thickness and density: its mass and inertia from the region's
/// integrals.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Plate {
    /// m = ρ t A (kg).
    pub mass: f64,
    /// The centroid S/A (m).
    pub centroid: P2,
    /// I_c = ρ t (J − |S|²/A) about the centroid, about the plate's normal (kg·m²).
    pub inertia: f64,
    /// A (m²).
    pub area: f64,
}

impl Plate {
    /// The plate of thickness `t` (m) and density `rho` (kg/m³) over the region whose
    /// integrals about the point `about` are `m` (m; [`region`]).
    pub fn new(m: &Moments, about: P2, t: f64, rho: f64) -> Plate {
        Plate {
            mass: rho * t * m.area,
            centroid: about + m.centroid(),
            inertia: rho * t * m.second_about_centroid(),
            area: m.area,
        }
    }
}
