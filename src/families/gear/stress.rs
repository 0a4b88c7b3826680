//! Hertz contact stress and load-weighted (Archard) wear of the eccentric cycloidal pair
//! under a stated driving torque (issue 38: the paper's future work, and its claim that the
//! wear is even).
//!
//! Exists because the sliding distance per flank ([`crate::families::gear::teeth`]) is a
//! wear measure without a load: which teeth wear first depends on the contact force and on
//! the flanks' curvature at K, and both vary around the eccentric pair's turn. Pure
//! geometry and statics of the pair built by [`crate::families::gear::model`].
//!
//! # The load model (the report states it)
//! One contact at a time (Camus: the tracing point K of the one generating circle through
//! the pitch point P), frictionless, quasi-static, constant driving torque T1 on gear 1.
//! The common normal d through K passes through P = (ρ1, 0), so its arm about O1 is
//! |P × d| = ρ1|d_y|. Gear 1 turns clockwise; D = σd points from gear 1 into gear 2
//! (σ = ±1 on an epicycloid/hypocycloid arch of gear 1), and the force F·D on gear 2
//! resists gear 1 only where the arm h = −σρ1 d_y is positive: there F = T1/h. Where h < 0
//! the flanks in contact are the back flanks, which cannot carry the driving torque. With
//! one contact at a time the pair therefore drives only over a fraction of each turn — for
//! e = 0 exactly one half, h = ρ1 σcos(ϕ/2) (the transverse contact ratio of teeth that
//! are single cycloid arches is 0.5).
//!
//! # Curvature of each flank at K (Euler–Savary)
//! Each flank is the path, in its gear's frame, of the tracing point K of the generating
//! circle (radius r) rolling on that gear's pitch curve. By Euler–Savary the centre of
//! curvature K* of that path lies on the line PK = 2r sin(ϕ/2)·d at
//! 1/PK − 1/PK* = 1/(D sin(ϕ/2)), D the inflection-circle diameter:
//! 1/D = 1/r − κ_f, κ_f the pitch curve's curvature counted positive where it bends
//! towards the circle. On gear 1's pitch circle κ_f = −σ/R; on gear 2's pitch curve
//! κ_f = σκ_p2 ([`GearPair::gear2_curvature`], closed form). Counting each flank's
//! curvature c_j positive where it is convex towards the other gear (D = σd points from gear
//! 1 into gear 2), c1 = −σ(D1/(2r) − 1)/(2r sin(ϕ/2)), c2 = σ(D2/(2r) − 1)/(2r sin(ϕ/2)),
//! and the relative curvature is 1/R* = c1 + c2 = D1 D2 (1/R + κ_p2)/(4r² sin(ϕ/2)). For a
//! circle these are the epi- and hypocycloids' radii 4r(R ± r)/(R ± 2r)·sin(ϕ/2); the tests
//! check gear 2's against circles through its drawn flank. Both vanish at the cusps.
//!
//! # Hertz (line contact of face width b) and Archard
//! p0 = sqrt(F E*/(π b R*)), contact half-width a_H = sqrt(4 F R*/(π b E*)),
//! E* = E/(2(1 − ν²)) for two flanks of one material. The load-weighted sliding of one
//! engagement is W = ∫ F |v_s| dt (N·m): Archard's wear volume of each flank is k·W (k in
//! m³/(N·m)), and the local wear depth per engagement of a flank point is k·(F/b)·|µ|.
//!
//! Both p0 and W grow without bound at the ends of a loaded stretch — at the cusp
//! (K = P, both flanks' radii of curvature vanish) and where the arm vanishes (a single
//! contact would need an infinite force) — so both are given on the working window: the
//! loaded stretch less the pole window w at each end.

use crate::families::gear::model::{Contact, GearPair};
use crate::families::gear::teeth::{gear2_arch_sums, simpson, Integral};
use crate::numeric::{brent_max, brent_root, minimize_1d, SearchError};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// The stated load and material of the teeth (`mechanism.load`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ToothLoad {
    /// Driving torque on gear 1, T1 (N·m), constant over the turn.
    pub torque: f64,
    /// Face width b (m).
    pub face_width: f64,
    /// Young's modulus E of both gears (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν of both gears.
    pub poisson_ratio: f64,
}

impl ToothLoad {
    /// E* = E/(2(1 − ν²)), the contact modulus of two bodies of one material (Pa).
    pub fn contact_modulus(&self) -> f64 {
        let nu = self.poisson_ratio;
        self.youngs_modulus / (2.0 * (1.0 - nu * nu))
    }
}

/// The contact at one α1 under the load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// α1 (rad).
    pub alpha1: f64,
    /// Arm h = −σρ1 d_y of the normal force about O1 (m): ≤ 0 where the flank in contact
    /// cannot drive.
    pub arm_m: f64,
    /// Normal force F = T1/h (N), 0 where h ≤ 0.
    pub force_n: f64,
    /// Curvatures c1, c2 of gear 1's and gear 2's flank at K, positive where convex towards
    /// the other gear (1/m).
    pub curvature: [f64; 2],
    /// Error bound of each (1/m).
    pub curvature_error: [f64; 2],
    /// Peak Hertz pressure p0 (Pa), 0 where unloaded.
    pub p0_pa: f64,
    /// Its error bound (Pa).
    pub p0_error_pa: f64,
    /// Contact half-width a_H (m), 0 where unloaded.
    pub half_width_m: f64,
}

/// The flanks' curvatures at α1 on arch i, each positive where convex towards the other
/// gear, with their error bounds (module doc, "Curvature"): with s = sin(ϕ/2),
/// 1/D1 = 1/r + σ/R, 1/D2 = 1/r − σκ_p2,
/// c1 = −σ(D1/(2r) − 1)/(2rs), c2 = σ(D2/(2r) − 1)/(2rs).
pub fn flank_curvatures(pair: &GearPair, alpha1: f64, arch: usize) -> ([f64; 2], [f64; 2]) {
    let ct = pair.contact_on(alpha1, arch);
    let (r, sigma) = (pair.r_gen, ct.sigma);
    let kp2 = pair.gear2_curvature(alpha1);
    let s = (0.5 * ct.phi).sin();
    let inv_d = [1.0 / r + sigma / pair.c.r_pitch, 1.0 / r - sigma * kp2];
    let c = [
        -sigma * (0.5 / (r * inv_d[0]) - 1.0) / (2.0 * r * s),
        sigma * (0.5 / (r * inv_d[1]) - 1.0) / (2.0 * r * s),
    ];
    // Rounding: ϕ carries N·κ·(the model's α1 shift) of it, which moves s by half that
    // times cos(ϕ/2); 1/D and D/(2r) − 1 cancel by (1/r + |κ|)·|D| and D/(2r)/|D/(2r) − 1|;
    // κ_p2 carries 32εκ of its own.
    let dphi = pair.n_arches as f64 * pair.condition() * pair.eval_shift(alpha1);
    let rel_s = 0.5 * dphi * (0.5 * ct.phi).cos().abs() / s.abs() + 4.0 * f64::EPSILON;
    let k_abs = [
        1.0 / pair.c.r_pitch,
        kp2.abs() * (1.0 + 32.0 * pair.condition()),
    ];
    let err = [0, 1].map(|j| {
        let dd = 1.0 / inv_d[j];
        let cancel = (0.5 * dd / r) / (0.5 * dd / r - 1.0).abs();
        let rel_d = 8.0 * f64::EPSILON * (1.0 / r + k_abs[j]) * dd.abs();
        c[j].abs() * (rel_s + cancel * (rel_d + 4.0 * f64::EPSILON))
    });
    (c, err)
}

/// The arm h = −σρ1 d_y of the normal about O1 at α1 on arch i (m).
pub fn arm(pair: &GearPair, alpha1: f64, arch: usize) -> f64 {
    arm_of(&pair.contact_on(alpha1, arch))
}

/// The arm h = −σρ1 d_y of a contact state (P = (ρ1, 0)).
fn arm_of(ct: &Contact) -> f64 {
    -ct.sigma * ct.p.x * ct.d.y
}

/// "addendum" on gear 1's epicycloid arches (even i), "dedendum" on its hypocycloid ones.
pub fn flank_name(arch: usize) -> &'static str {
    if arch.is_multiple_of(2) {
        "addendum"
    } else {
        "dedendum"
    }
}

/// The contact at α1 on arch i under the load (module doc).
pub fn hertz_on(pair: &GearPair, alpha1: f64, arch: usize, load: &ToothLoad) -> Hertz {
    let h = arm(pair, alpha1, arch);
    let (c, ce) = flank_curvatures(pair, alpha1, arch);
    let mut out = Hertz {
        alpha1,
        arm_m: h,
        force_n: 0.0,
        curvature: c,
        curvature_error: ce,
        p0_pa: 0.0,
        p0_error_pa: 0.0,
        half_width_m: 0.0,
    };
    if h <= 0.0 {
        return out;
    }
    let f = load.torque / h;
    let kr = c[0] + c[1];
    let es = load.contact_modulus();
    let p0 = (f * es * kr / (PI * load.face_width)).sqrt();
    // Relative errors: the curvature sum's bound, and the arm's rounding 8ε(ρ1 + a)/h.
    let rel_k = (ce[0] + ce[1]) / kr.abs();
    let rel_f = 8.0 * f64::EPSILON * (pair.c.rho1(alpha1) + pair.a) / h;
    out.force_n = f;
    out.p0_pa = p0;
    out.p0_error_pa = 0.5 * p0 * (rel_k + rel_f) + 4.0 * f64::EPSILON * p0;
    out.half_width_m = (4.0 * f / (PI * load.face_width * es * kr)).sqrt();
    out
}

/// One extreme of p0 on a working window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressPoint {
    /// α1 (rad).
    pub alpha1: f64,
    /// p0 (Pa) and its error bound.
    pub p0_pa: f64,
    pub error_pa: f64,
}

/// The loaded stretch of one arch of gear 1 and its figures.
#[derive(Debug, Clone, PartialEq)]
pub struct ArchStress {
    /// Arch index i of gear 1.
    pub arch: usize,
    /// The α1 range over which the arch's contact can drive (the arm h > 0).
    pub loaded: (f64, f64),
    /// The working window: `loaded` less the pole window at each end (`None` if empty).
    pub window: Option<(f64, f64)>,
    /// Largest p0 on the window (at one of its ends, where p0 grows without bound).
    pub peak: Option<StressPoint>,
    /// Least p0 on the window (inside it).
    pub least: Option<StressPoint>,
    /// W = ∫ F |v_s| dt over the window, one engagement (N·m).
    pub archard: Integral,
    /// (α1, p0) at 65 evenly spaced points of the window, ends included (for the plot).
    pub samples: Vec<(f64, f64)>,
}

impl ArchStress {
    /// The error bound of both extremes of p0 (Pa; `None` with an empty window).
    pub fn p0_error(&self) -> Option<f64> {
        self.peak
            .map(|p| p.error_pa.max(self.least.map_or(0.0, |l| l.error_pa)))
    }
}

/// The load-weighted wear and stress of every flank over a cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct FlankStress {
    /// Per arch of gear 1 (one turn of gear 1).
    pub arches: Vec<ArchStress>,
    /// Gear 1, arch i: n1 engagements per cycle, n1·W_i (N·m), with error.
    pub gear1: Vec<(f64, f64)>,
    /// Gear 2, arch g: Σ W over its n2 engagements per cycle (N·m), with error.
    pub gear2: Vec<(f64, f64)>,
    /// Fraction of a turn of gear 1 over which the contact can drive, and its error bound.
    pub driving_fraction: (f64, f64),
    /// The pole window left out at each end of a loaded stretch (rad).
    pub window_rad: f64,
}

/// Where on arch i the arm changes sign: sampled at 64 points, each change located by
/// Brent to 1e-15 rad; returns the loaded sub-intervals (arm > 0) and the roots' error.
fn loaded_stretches(pair: &GearPair, arch: usize) -> Result<(Vec<(f64, f64)>, f64), SearchError> {
    let (a0, a1) = (pair.arch_start(arch), pair.arch_start(arch + 1));
    const M: usize = 64;
    let xs: Vec<f64> = (0..=M)
        .map(|k| a0 + (a1 - a0) * k as f64 / M as f64)
        .collect();
    let f = |x: f64| arm(pair, x, arch);
    let mut cuts = vec![a0];
    let mut err: f64 = 0.0;
    for w in xs.windows(2) {
        let (fa, fb) = (f(w[0]), f(w[1]));
        if fa == 0.0 && w[0] > a0 {
            // A sample on the root itself.
            cuts.push(w[0]);
            err = err.max(pair.eval_shift(w[0]));
        } else if fa * fb < 0.0 {
            let r = brent_root(f, w[0], w[1], 1e-15)?;
            cuts.push(r.x);
            err = err.max(1e-15 + pair.eval_shift(r.x));
        }
    }
    cuts.push(a1);
    let out = cuts
        .windows(2)
        .filter(|w| f(0.5 * (w[0] + w[1])) > 0.0)
        .map(|w| (w[0], w[1]))
        .collect();
    Ok((out, err))
}

/// The window's samples (α1, p0) at 65 evenly spaced points, ends included.
type Samples = Vec<(f64, f64)>;

/// Largest and least p0 on the window [lo, hi]: 64 samples plus both ends, the largest
/// refined by Brent where it is inside, the least by Brent between its neighbours; and the
/// samples.
fn extremes(
    pair: &GearPair,
    arch: usize,
    load: &ToothLoad,
    (lo, hi): (f64, f64),
) -> Result<(StressPoint, StressPoint, Samples), SearchError> {
    const M: usize = 64;
    let at = |x: f64| hertz_on(pair, x, arch, load);
    let point = |h: Hertz| StressPoint {
        alpha1: h.alpha1,
        p0_pa: h.p0_pa,
        error_pa: h.p0_error_pa,
    };
    let step = (hi - lo) / M as f64;
    let xs: Vec<f64> = (0..=M).map(|k| lo + step * k as f64).collect();
    let ps: Vec<f64> = xs.iter().map(|&x| at(x).p0_pa).collect();
    let imax = (0..=M).fold(0, |b, k| if ps[k] > ps[b] { k } else { b });
    let imin = (0..=M).fold(0, |b, k| if ps[k] < ps[b] { k } else { b });
    let around = |k: usize| (xs[k.saturating_sub(1)], xs[(k + 1).min(M)]);
    let xtol = 1e-12 * (1.0 + lo.abs());
    let peak = if imax == 0 || imax == M {
        point(at(xs[imax]))
    } else {
        let (a, b) = around(imax);
        point(at(brent_max(|x| at(x).p0_pa, a, b, xtol)?.x))
    };
    let (a, b) = around(imin);
    let least = point(at(minimize_1d(|x| at(x).p0_pa, a, b, xtol)?.x));
    Ok((peak, least, xs.into_iter().zip(ps).collect()))
}

/// The stress and wear figures of arch i's loaded stretch (the stretch that ends at the
/// arch's cusp when an arch has more than one — never seen, but not assumed away).
fn arch_stress(
    pair: &GearPair,
    arch: usize,
    load: &ToothLoad,
    window: f64,
) -> Result<(ArchStress, f64, f64), SearchError> {
    let (stretches, root_err) = loaded_stretches(pair, arch)?;
    let loaded_len: f64 = stretches.iter().map(|s| s.1 - s.0).sum();
    let (lo, hi) = stretches.first().copied().unwrap_or((0.0, 0.0));
    let win = (hi - lo > 2.0 * window).then_some((lo + window, hi - window));
    let (peak, least, samples) = match win {
        Some(w) => {
            let (p, l, s) = extremes(pair, arch, load, w)?;
            (Some(p), Some(l), s)
        }
        None => (None, None, Vec::new()),
    };
    let f = |x: f64| {
        let ct = pair.contact_on(x, arch);
        load.torque / arm_of(&ct) * ct.v_slide.abs() / pair.omega1
    };
    // W: the half of the window next to the tip (where the arm vanishes and F|v_s| grows
    // like 1/|α − tip|) in u = ln|α − tip|, where f·e^u is smooth; the half next to the cusp
    // in α. Each half converges in a few dozen Simpson points.
    let archard = match win {
        Some((a, b)) => {
            let min_arm = arm(pair, a, arch).min(arm(pair, b, arch));
            let cond = pair.condition() * (pair.c.rho1(a) + pair.a) / min_arm;
            let tip_hi = arm(pair, hi, arch).abs() < arm(pair, lo, arch).abs();
            let (tip, dir) = if tip_hi { (hi, -1.0) } else { (lo, 1.0) };
            let mid = 0.5 * (a + b);
            let g = |u: f64| {
                let d = u.exp();
                f(tip + dir * d) * d
            };
            let near = simpson(g, window.ln(), (mid - tip).abs().ln(), 1e-10, cond);
            let (c0, c1) = if tip_hi { (a, mid) } else { (mid, b) };
            let rest = simpson(f, c0, c1, 1e-10, cond);
            Integral {
                value: near.value + rest.value,
                error: near.error + rest.error,
                n: near.n + rest.n,
            }
        }
        None => Integral {
            value: 0.0,
            error: 0.0,
            n: 0,
        },
    };
    let stress = ArchStress {
        arch,
        loaded: (lo, hi),
        window: win,
        peak,
        least,
        archard,
        samples,
    };
    Ok((stress, loaded_len, 2.0 * root_err * stretches.len() as f64))
}

/// [`FlankStress`] of the pair over a cycle of n1 turns of gear 1 (n2 of gear 2), the pole
/// window `window` (rad) left out at each end of a loaded stretch.
pub fn flank_stress(
    pair: &GearPair,
    turns1: u32,
    turns2: u32,
    load: &ToothLoad,
    window: f64,
) -> Result<FlankStress, SearchError> {
    let per: Vec<(ArchStress, f64, f64)> = (0..pair.n_arches)
        .into_par_iter()
        .map(|i| arch_stress(pair, i, load, window))
        .collect::<Result<_, _>>()?;
    let fraction = per.iter().map(|p| p.1).sum::<f64>() / TAU;
    let fraction_err = per.iter().map(|p| p.2).sum::<f64>() / TAU;
    let w: Vec<(f64, f64)> = per
        .iter()
        .map(|p| (p.0.archard.value, p.0.archard.error))
        .collect();
    let n1 = turns1 as f64;
    Ok(FlankStress {
        gear1: w.iter().map(|&(v, e)| (n1 * v, n1 * e)).collect(),
        gear2: gear2_arch_sums(&w, turns1, turns2),
        arches: per.into_iter().map(|p| p.0).collect(),
        driving_fraction: (fraction, fraction_err),
        window_rad: window,
    })
}
