//! Tooth-level figures of the eccentric cycloidal pair (issue 19): the tooth outlines of both
//! gears in their own frames, the contact-point radii and velocities (the paper's Fig. 5
//! and 6), the sliding distance per tooth flank (a wear measure), the sliding coefficients
//! of the circular cycloidal and involute equivalents, and the pole margin min |cos β|.
//!
//! Exists because these are pure geometry of the pair built by [`crate::families::gear::model`]
//! (which places the contact point K by Camus' theorem), needed by the report, the drawing
//! and the tests; nothing here solves or designs.
//!
//! # Frames
//! Gear 1's frame: origin O1, x towards the pitch circle's centre C (the fixed frame at
//! α1 = 0). Gear 1 turns clockwise by α1, so a point K of the fixed frame is the point
//! K₁ = Rot(α1)·K of gear 1. Gear 2's frame: origin O2, axes those of the fixed frame at
//! α1 = 0; gear 2 turns counter-clockwise by α2(α1), so K₂ = Rot(−α2)·(K − O2).

use crate::families::gear::model::{Alpha2Map, GearPair};
use crate::geom::{rot, P2};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// α1 (within the turn, in [α_i, α_{i+1}]) at which the generating circle has rolled the
/// angle ϕ ∈ [0, 2π] along gear 1's arch i: θ = (2πi + ϕ)/N, α1 = θ − atan2(e sin θ,
/// R + e cos θ); the arch ends are the model's exact cusps.
pub fn alpha_at(pair: &GearPair, arch: usize, phi: f64) -> f64 {
    if phi <= 0.0 {
        return pair.arch_start(arch);
    }
    if phi >= TAU {
        return pair.arch_start(arch + 1);
    }
    let n = pair.n_arches as f64;
    pair.c.alpha_of_theta((TAU * arch as f64 + phi) / n)
}

/// One arch of a tooth outline in its gear's own frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Arch {
    /// Arch index on its gear (gear 1: 0 … N − 1; gear 2: 0 … N·n1/n2 − 1).
    pub index: usize,
    /// Epicycloid (addendum, the tooth) or hypocycloid (dedendum, the space) on its gear.
    pub epicycloid: bool,
    /// Rolling angle ϕ of each point (rad), 0 … 2π equally spaced.
    pub phi: Vec<f64>,
    /// The points (m), gear frame.
    pub points: Vec<P2>,
}

/// Both tooth outlines, arch by arch.
#[derive(Debug, Clone, PartialEq)]
pub struct Profiles {
    /// Gear 1's N arches (one turn of gear 1).
    pub gear1: Vec<Arch>,
    /// Gear 2's N·n1/n2 arches (one turn of gear 2 = n1/n2 turns of gear 1).
    pub gear2: Vec<Arch>,
    /// |K₂(end of the last arch) − K₂(start of the first)| (m): how far gear 2's outline
    /// misses closing after its full turn (the closure of α2, times ρ2).
    pub gear2_closure_gap_m: f64,
}

/// The tooth outlines as the locus of the contact point in each gear's frame, `m` + 1 points
/// per arch (ϕ = 2πk/m). Gear 1's arch i is traced while α1 ∈ [α_i, α_{i+1}] (epicycloid for
/// even i); gear 2's arch g while gear 1 is on its global arch g (α1 = 2π⌊g/N⌋ + α on arch
/// g mod N) and is a hypocycloid where gear 1's is an epicycloid (the generating circle lies
/// inside gear 2's pitch curve there), so tooth meets space.
pub fn profiles(pair: &GearPair, a2: &Alpha2Map, turns1: u32, turns2: u32, m: usize) -> Profiles {
    let n = pair.n_arches;
    let m = m.max(2);
    let o2 = P2::new(pair.a, 0.0);
    let phis: Vec<f64> = (0..=m).map(|k| TAU * k as f64 / m as f64).collect();
    // The arches in parallel (each a few hundred contact points), collected in order.
    let gear1 = (0..n)
        .into_par_iter()
        .map(|i| Arch {
            index: i,
            epicycloid: i.is_multiple_of(2),
            phi: phis.clone(),
            points: phis
                .iter()
                .map(|&ph| {
                    let x = alpha_at(pair, i, ph);
                    rot(x, pair.contact_on(x, i).k)
                })
                .collect(),
        })
        .collect();
    let arches2 = n * turns1 as usize / turns2 as usize;
    let k2 = |g: usize, ph: f64| {
        let i = g % n;
        let x = alpha_at(pair, i, ph);
        let xg = TAU * (g / n) as f64 + x;
        rot(-a2.alpha2(xg), pair.contact_on(x, i).k - o2)
    };
    let gear2 = (0..arches2)
        .into_par_iter()
        .map(|g| Arch {
            index: g,
            epicycloid: !(g % n).is_multiple_of(2),
            phi: phis.clone(),
            points: phis.iter().map(|&ph| k2(g, ph)).collect(),
        })
        .collect();
    let gap = if arches2 > 0 {
        (k2(arches2 - 1, TAU) - k2(0, 0.0)).norm()
    } else {
        0.0
    };
    Profiles {
        gear1,
        gear2,
        gear2_closure_gap_m: gap,
    }
}

/// The contact point's radii and velocities at one α1 (the paper's Fig. 5 and 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactKinematics {
    /// α1 (rad).
    pub alpha1: f64,
    /// ρ_K1 = |O1K| (m).
    pub rho_k1: f64,
    /// ρ_K2 = |O2K| (m).
    pub rho_k2: f64,
    /// V_K1 = ω1·ρ_K1 (m/s): speed of gear 1's point at K.
    pub v_k1: f64,
    /// V_K2 = ω2·ρ_K2, ω2 = ω1 ρ1/ρ2 (m/s): speed of gear 2's point at K.
    pub v_k2: f64,
    /// v_t1 = V_K1·τ (m/s), τ the common tangent.
    pub v_t1: f64,
    /// v_t2 = V_K2·τ (m/s).
    pub v_t2: f64,
    /// Sliding velocity v_s = v_t1 − v_t2 (m/s).
    pub v_slide: f64,
    /// cos β1 = v_t1/V_K1 (–): zero at a pole of µ1.
    pub cos_beta1: f64,
    /// cos β2 = v_t2/V_K2 (–): zero at a pole of µ2.
    pub cos_beta2: f64,
}

/// [`ContactKinematics`] at α1 on the arch containing it.
pub fn contact_kinematics(pair: &GearPair, alpha1: f64) -> ContactKinematics {
    let ct = pair.contact(alpha1);
    let r1 = pair.c.rho1(alpha1);
    let omega2 = pair.omega1 * r1 / (pair.a - r1);
    let rho_k1 = ct.k.norm();
    let rho_k2 = (ct.k - P2::new(pair.a, 0.0)).norm();
    let (v_k1, v_k2) = (pair.omega1 * rho_k1, omega2 * rho_k2);
    ContactKinematics {
        alpha1,
        rho_k1,
        rho_k2,
        v_k1,
        v_k2,
        v_t1: ct.vt1,
        v_t2: ct.vt2,
        v_slide: ct.v_slide,
        cos_beta1: ct.vt1 / v_k1,
        cos_beta2: ct.vt2 / v_k2,
    }
}

/// A definite integral with its error bound.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integral {
    /// The value.
    pub value: f64,
    /// Bound on its error: |S(n) − S(n/2)| of the last two Simpson rules (Richardson says
    /// the error of S(n) is about a fifteenth of that) plus 64ε·|S|.
    pub error: f64,
    /// Points of the last rule.
    pub n: usize,
}

/// Sliding distance of one engagement of gear 1's arch i (m), the wear measure of issue 19:
///
/// s_i = ∫ |v_s| dt = ∫_{α_i}^{α_{i+1}} |v_t1 − v_t2| dα1/ω1 = ∫ (a/ρ2)·2r sin(ϕ/2) dα1,
///
/// the relative slip of the two flanks while this arch is in contact. Both flanks slide by the
/// same distance; µ has poles (v_t → 0) but v_s = (Ω1 − Ω2)·2r sin(ϕ/2) stays finite, so the
/// integrand is smooth and composite Simpson (n doubled from 16 until two rules agree to
/// `rtol`) converges. For e = 0 it is 8r²a/(R(a − R)).
pub fn arch_sliding_distance(pair: &GearPair, arch: usize, rtol: f64) -> Integral {
    let (a0, a1) = (pair.arch_start(arch), pair.arch_start(arch + 1));
    let f = |x: f64| pair.contact_on(x, arch).v_slide.abs() / pair.omega1;
    simpson(f, a0, a1, rtol, pair.condition())
}

/// ∫_{a0}^{a1} f by composite Simpson, n doubled from 16 until two rules agree to `rtol`
/// (at most 2¹⁶ points); the error bound is their difference plus 64ε·`cond`·|S|, `cond`
/// the integrand's relative rounding in units of ε/64 (written out: two lines of Simpson
/// with the project's own error bound, which no quadrature crate reports this way).
pub fn simpson<F: Fn(f64) -> f64>(f: F, a0: f64, a1: f64, rtol: f64, cond: f64) -> Integral {
    let rule = |n: usize| {
        let h = (a1 - a0) / n as f64;
        let mut s = f(a0) + f(a1);
        for k in 1..n {
            s += f(a0 + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    };
    let mut n = 16;
    let mut prev = rule(n);
    loop {
        n *= 2;
        let cur = rule(n);
        let diff = (cur - prev).abs();
        if diff <= rtol * cur.abs() || n >= 1 << 16 {
            return Integral {
                value: cur,
                error: diff + 64.0 * f64::EPSILON * cond * cur.abs(),
                n,
            };
        }
        prev = cur;
    }
}

/// Sliding distance per tooth flank (arch) of both gears over one cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct FlankWear {
    /// Per engagement of gear 1's arch i (one turn of gear 1), i = 0 … N − 1.
    pub per_engagement: Vec<Integral>,
    /// Gear 1, arch i: n1 engagements per cycle, n1·s_i (m).
    pub gear1: Vec<(f64, f64)>,
    /// Gear 2, arch g: its n2 engagements per cycle are the global arches g + kM
    /// (M = N·n1/n2), each with gear 1's arch (g + kM) mod N: Σ s (m), with error.
    pub gear2: Vec<(f64, f64)>,
    /// Engagements per cycle of each arch of gear 1 (n1) and of gear 2 (n2).
    pub engagements: (u32, u32),
}

/// [`FlankWear`] of the pair over a cycle of n1 turns of gear 1 (n2 of gear 2).
pub fn flank_wear(pair: &GearPair, turns1: u32, turns2: u32, rtol: f64) -> FlankWear {
    let n = pair.n_arches;
    // The arches' integrals in parallel, collected in order (the same numbers whatever the
    // threads).
    let per: Vec<Integral> = (0..n)
        .into_par_iter()
        .map(|i| arch_sliding_distance(pair, i, rtol))
        .collect();
    let gear1 = per
        .iter()
        .map(|s| (turns1 as f64 * s.value, turns1 as f64 * s.error))
        .collect();
    let values: Vec<(f64, f64)> = per.iter().map(|s| (s.value, s.error)).collect();
    let gear2 = gear2_arch_sums(&values, turns1, turns2);
    FlankWear {
        per_engagement: per,
        gear1,
        gear2,
        engagements: (turns1, turns2),
    }
}

/// Per arch g of gear 2, the sum over its n2 engagements per cycle of a per-engagement
/// figure of gear 1's arches (value, error): gear 2 has M = N·n1/n2 arches, and its arch g
/// meets gear 1's arches (g + kM) mod N, k = 0 … n2 − 1.
pub fn gear2_arch_sums(per: &[(f64, f64)], turns1: u32, turns2: u32) -> Vec<(f64, f64)> {
    let n = per.len();
    let m = n * turns1 as usize / turns2 as usize;
    (0..m)
        .map(|g| {
            (0..turns2 as usize)
                .map(|k| per[(g + k * m) % n])
                .fold((0.0, 0.0), |(v, e), s| (v + s.0, e + s.1))
        })
        .collect()
}

/// Sliding coefficients of the circular cycloidal pair (e = 0) with the same R, r and mean
/// ratio u = n1/n2: ρ1 = R, ρ2 = uR, a = (1 + u)R; on an arch of gear 1 with σ = +1
/// (addendum) or −1 (dedendum) µ1 = 2ra/(ρ2(σρ1 + 2r)) and µ2 = −µ1/(1 − µ1), constant
/// along the arch. Returns (µ1, µ2) on the addendum and on the dedendum arch.
pub fn circular_cycloidal_mu(r_pitch: f64, r_gen: f64, u: f64) -> [(f64, f64); 2] {
    let (r1, r2) = (r_pitch, u * r_pitch);
    let a = r1 + r2;
    [1.0, -1.0].map(|sigma| {
        let mu1 = 2.0 * r_gen * a / (r2 * (sigma * r1 + 2.0 * r_gen));
        (mu1, -mu1 / (1.0 - mu1))
    })
}

/// The involute pair with the same module and mean ratio (addendum h_a·m, profile shifts
/// x₁ = −x₂: the standard centre distance and pressure angle kept).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Involute {
    /// Module m (m).
    pub module_m: f64,
    /// z1 and z2 (z2 = u·z1).
    pub z1: f64,
    pub z2: f64,
    /// Pressure angle α (rad).
    pub pressure_angle_rad: f64,
    /// Profile shift coefficients (x₁, x₂ = −x₁); (0, 0) for the standard pair.
    pub shift: [f64; 2],
    /// Centre distance m(z1 + z2)/2 (m).
    pub center_distance_m: f64,
    /// N1N2 = a sin α (m): the line of action between the base-circle tangency points.
    pub line_of_action_m: f64,
    /// Start A of contact, distance from N1 (m): g − sqrt(ra2² − rb2²).
    pub x_start_m: f64,
    /// End E of contact, distance from N1 (m): sqrt(ra1² − rb1²).
    pub x_end_m: f64,
    /// Contact ratio (x_E − x_A)/(πm cos α).
    pub contact_ratio: f64,
    /// µ1 = 1 − (g − x)/(u x) at A and at E.
    pub mu1_start: f64,
    pub mu1_end: f64,
    /// µ2 = 1 − u x/(g − x) at A and at E.
    pub mu2_start: f64,
    pub mu2_end: f64,
    /// Whether the path reaches N1 or N2 (x_A ≤ 0 or x_E ≥ g): interference, a pole of µ on
    /// the path.
    pub interference: bool,
}

impl Involute {
    /// The largest |µ| on the path: µ1 and µ2 are monotonic in x, so an end's.
    pub fn peak_mu(&self) -> f64 {
        [self.mu1_start, self.mu1_end, self.mu2_start, self.mu2_end]
            .iter()
            .fold(0.0, |a: f64, b| a.max(b.abs()))
    }
}

/// The standard involute equivalent in closed form ([`involute_shifted`] with no shift).
pub fn involute(module: f64, z1: f64, z2: f64, alpha: f64, addendum: f64) -> Involute {
    involute_shifted(module, z1, z2, alpha, addendum, 0.0)
}

/// The involute equivalent in closed form, gear 1 shifted by x₁·m and gear 2 by −x₁·m (tip
/// radii r_ai = r_i + (h_a + x_i)m; the centre distance and α unchanged). Along the line of
/// action x from N1 the flanks' radii of curvature are x and g − x, so v_t1 = ω1 x,
/// v_t2 = ω2 (g − x), ω2 = ω1/u, and µ1 = (v_t1 − v_t2)/v_t1, µ2 = (v_t2 − v_t1)/v_t2 are
/// monotonic in x: their extremes are at the ends of the path, A (gear 1's root) and E
/// (gear 1's tip).
pub fn involute_shifted(
    module: f64,
    z1: f64,
    z2: f64,
    alpha: f64,
    addendum: f64,
    x1: f64,
) -> Involute {
    let (r1, r2) = (0.5 * module * z1, 0.5 * module * z2);
    let u = z2 / z1;
    let (rb1, rb2) = (r1 * alpha.cos(), r2 * alpha.cos());
    let (ra1, ra2) = (r1 + (addendum + x1) * module, r2 + (addendum - x1) * module);
    let a = r1 + r2;
    let g = a * alpha.sin();
    let xa = g - ((ra2 - rb2) * (ra2 + rb2)).sqrt();
    let xe = ((ra1 - rb1) * (ra1 + rb1)).sqrt();
    let mu1 = |x: f64| 1.0 - (g - x) / (u * x);
    let mu2 = |x: f64| 1.0 - u * x / (g - x);
    Involute {
        module_m: module,
        z1,
        z2,
        pressure_angle_rad: alpha,
        shift: [x1, -x1],
        center_distance_m: a,
        line_of_action_m: g,
        x_start_m: xa,
        x_end_m: xe,
        contact_ratio: (xe - xa) / (std::f64::consts::PI * module * alpha.cos()),
        mu1_start: mu1(xa),
        mu1_end: mu1(xe),
        mu2_start: mu2(xa),
        mu2_end: mu2(xe),
        interference: xa <= 0.0 || xe >= g,
    }
}

/// The least profile shift without undercut by a rack cutter of addendum h_a:
/// x_min = h_a − (z/2) sin²α.
pub fn undercut_limit(z: f64, alpha: f64, addendum: f64) -> f64 {
    addendum - 0.5 * z * alpha.sin().powi(2)
}

/// The tooth's thickness at its tip circle (m): s_a = d_a [π/(2z) + 2x tan α/z + inv α −
/// inv α_a], inv t = tan t − t, cos α_a = d_b/d_a (the standard tooth-thickness formula).
pub fn tip_thickness(module: f64, z: f64, alpha: f64, addendum: f64, x: f64) -> f64 {
    let inv = |t: f64| t.tan() - t;
    let d = module * z;
    let da = d + 2.0 * (addendum + x) * module;
    let alpha_a = (d * alpha.cos() / da).acos();
    da * (std::f64::consts::PI / (2.0 * z) + 2.0 * x * alpha.tan() / z + inv(alpha) - inv(alpha_a))
}

/// The least tip thickness a shifted involute pair may have, over the module (the usual
/// rule against pointed teeth, e.g. Niemann–Winter: 0.2–0.4 m).
pub const MIN_TIP_THICKNESS: f64 = 0.25;

/// The least contact ratio a shifted involute pair may have.
pub const MIN_CONTACT_RATIO: f64 = 1.1;

/// The profile-shifted involute pair with the least peak specific sliding: x₁ = −x₂ chosen so
/// that gear 1's root sliding |µ1(A)| equals gear 2's |µ2(E)| (the usual balance: one rises
/// and the other falls with x₁, so their larger is least where they meet), within the shifts
/// that keep both teeth free of undercut ([`undercut_limit`]), their tips at least
/// [`MIN_TIP_THICKNESS`]·m thick, the contact ratio at least [`MIN_CONTACT_RATIO`] and the
/// path off N1, N2; at an edge of that interval when the balance lies outside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BalancedShift {
    /// The pair at the chosen shift.
    pub pair: Involute,
    /// The admissible interval of x₁.
    pub interval: [f64; 2],
    /// `None` when balanced inside the interval; else the edge's reason.
    pub binding: Option<&'static str>,
    /// Both teeth's tip thickness (m).
    pub tip_thickness_m: [f64; 2],
}

/// Why x₁ is not admissible (first reason), or `None`.
fn shift_fault(m: f64, z1: f64, z2: f64, alpha: f64, ha: f64, x1: f64) -> Option<&'static str> {
    let p = involute_shifted(m, z1, z2, alpha, ha, x1);
    if x1 < undercut_limit(z1, alpha, ha) {
        Some("gear 1's undercut")
    } else if -x1 < undercut_limit(z2, alpha, ha) {
        Some("gear 2's undercut")
    } else if tip_thickness(m, z1, alpha, ha, x1) < MIN_TIP_THICKNESS * m {
        Some("gear 1's tip thickness")
    } else if tip_thickness(m, z2, alpha, ha, -x1) < MIN_TIP_THICKNESS * m {
        Some("gear 2's tip thickness")
    } else if p.contact_ratio < MIN_CONTACT_RATIO || p.interference {
        Some("the contact ratio")
    } else {
        None
    }
}

/// The balanced shift ([`BalancedShift`]): the admissible interval from a scan of x₁ over
/// [−2, 2] in steps of 0.001 refined to 1e-12 by bisection at both ends, then the balance
/// |µ1(A)| = |µ2(E)| by bisection (monotonic in x₁). `None` when no shift is admissible.
pub fn balanced_shift(m: f64, z1: f64, z2: f64, alpha: f64, ha: f64) -> Option<BalancedShift> {
    let ok = |x: f64| shift_fault(m, z1, z2, alpha, ha, x).is_none();
    let grid: Vec<f64> = (0..=4000).map(|k| -2.0 + 0.001 * k as f64).collect();
    let first = grid.iter().position(|&x| ok(x))?;
    let last = grid.iter().rposition(|&x| ok(x))?;
    let edge = |inside: f64, outside: f64| {
        let (mut a, mut b) = (inside, outside);
        for _ in 0..60 {
            let c = 0.5 * (a + b);
            if ok(c) {
                a = c;
            } else {
                b = c;
            }
        }
        a
    };
    let lo = if first == 0 {
        grid[0]
    } else {
        edge(grid[first], grid[first - 1])
    };
    let hi = if last == grid.len() - 1 {
        grid[last]
    } else {
        edge(grid[last], grid[last + 1])
    };
    let g = |x: f64| {
        let p = involute_shifted(m, z1, z2, alpha, ha, x);
        p.mu1_start.abs() - p.mu2_end.abs()
    };
    let (x1, binding) = if g(lo) <= 0.0 {
        (lo, shift_fault(m, z1, z2, alpha, ha, lo - 1e-9))
    } else if g(hi) >= 0.0 {
        (hi, shift_fault(m, z1, z2, alpha, ha, hi + 1e-9))
    } else {
        let (mut a, mut b) = (lo, hi);
        for _ in 0..100 {
            let c = 0.5 * (a + b);
            if g(c) > 0.0 {
                a = c;
            } else {
                b = c;
            }
        }
        (0.5 * (a + b), None)
    };
    Some(BalancedShift {
        pair: involute_shifted(m, z1, z2, alpha, ha, x1),
        interval: [lo, hi],
        binding,
        tip_thickness_m: [
            tip_thickness(m, z1, alpha, ha, x1),
            tip_thickness(m, z2, alpha, ha, -x1),
        ],
    })
}

/// Whether µ1 (`j` = 1) or µ2 (`j` = 2) must have a pole on gear 1's arch i, for every
/// generating radius r: the pole function (K − O_j)·d tends to ∓ρ_j sin ψ_i at ϕ → 0⁺ and to
/// ±ρ_j sin ψ_{i+1} at ϕ → 2π⁻ (K → P, d → ∓T at the two cusps, T·(P − O_j) = ±ρ_j sin ψ),
/// and ψ keeps its sign between the cusps of an arch that does not start or end at a
/// ψ = 0 cusp (α1 ∈ {0, π}); so the function changes sign inside the arch and µ_j has a
/// pole there (intermediate value theorem). This is the certificate that no choice of r, R
/// or a removes the poles of a full cusp-to-cusp cycloidal arch when e > 0: only arches
/// bounded by a ψ = 0 cusp may be free of them. Returns the arches with a certified pole.
pub fn certified_pole_arches(pair: &GearPair) -> Vec<usize> {
    if pair.c.e == 0.0 {
        return Vec::new();
    }
    (0..pair.n_arches)
        .filter(|&i| !pair.cusp_is_indeterminate(i) && !pair.cusp_is_indeterminate(i + 1))
        .filter(|&i| {
            let s0 = pair.arch_start(i).sin();
            let s1 = pair.arch_start(i + 1).sin();
            s0 * s1 > 0.0
        })
        .collect()
}
