//! Effects the scene's model leaves out or includes, each with a bound computed from the
//! scene as resolved (and from the reference solution's design), stated against the
//! headline objective. One function per family; the pure physics is in [`crate::mech`].

use crate::problem::{Scene, SceneKind};
use crate::report::SolveResult;
use crate::families::crane::model::{head_heights, head_heights_with, Linkage};
use crate::families::gear::model::{GearPair, Pole, Singularities, Which};
use crate::families::hypocycloid::model::{max_abs_y, Hypocycloid};
use crate::families::slider_crank::model::Kinematics;
use crate::families::hypocycloid::synth::CoefficientModel;
use std::f64::consts::TAU;

/// Standard gravity (m/s²).
const G: f64 = 9.80665;

/// One entry: (effect, what is left out or included, with its bound).
pub type Effect = (String, String);

/// What the scene's model leaves out or includes, with a numeric bound for each effect that
/// the scene's data allow (and a plain statement where they do not). `reference` is the
/// solution at the tightest settings; its headline value is `headline`.
pub fn effects(scene: &Scene, reference: &SolveResult, headline: f64) -> Vec<Effect> {
    match &scene.kind {
        SceneKind::SliderCrank(s) => slider_crank(s, headline),
        SceneKind::Hypocycloid(h) => hypocycloid(h, reference, headline),
        SceneKind::LuffingCrane(c) => crane(c, reference, headline),
        SceneKind::EccentricGear(g) => gear(g, reference, headline),
    }
}

fn rel(x: f64, headline: f64) -> f64 {
    x / headline.abs().max(1e-300)
}

fn slider_crank(s: &crate::families::slider_crank::file::SliderCrankScene, reference: f64) -> Vec<Effect> {
    let c = &s.core;
    let m = &c.mech;
    let w2 = c.omega * c.omega;
    let n = 3600;
    let phis: Vec<f64> = (0..n).map(|k| k as f64 * TAU / n as f64).collect();
    let mut out = Vec::new();
    // Gravity against inertia. The shaking force is the inertia force only (the weights are
    // a static load, reported as `derived` static weight); gravity enters the drive torque.
    let weight = (m.crank.mass + m.rod.mass + m.slider_mass) * G;
    let ratio = G / (m.r * w2);
    let mut tg = 0.0f64;
    for &p in &phis {
        if let Some(st) = m.state(p) {
            let v = m.crank.mass * m.crank.centroid
                + m.rod.mass * st.g3[1].norm()
                + m.slider_mass * st.x[1].abs();
            tg = tg.max(G * v);
        }
    }
    if c.loads.gravity.norm() > 0.0 {
        out.push((
            "gravity".into(),
            format!("modelled (g/(Rω²) = {ratio:.3}: weights matter for the torque; the link weights' torque reaches up to {tg:.4} N·m)"),
        ));
    } else {
        out.push((
            "gravity".into(),
            format!(
                "left out: g/(Rω²) = {ratio:.2e}. The shaking force is inertial and does not change; the link weights W = {weight:.4} N are a static load ({:.2e} of the headline value {reference:.6}); their torque, g·max(m2 r2 + m3|G3'| + m4|x'|) = {tg:.4} N·m, is left out of the drive torque (plus the counterweight's |U|·g = {:.4} N·m per kg·m of unbalance)",
                rel(weight, reference),
                G
            ),
        ));
    }
    // Rod inertia against the lumped split.
    let lumped_i = m.rod.mass * (m.l - m.rod.centroid) * m.rod.centroid;
    let uniform_i = m.rod.mass * m.l * m.l / 12.0;
    let centred = (m.rod.centroid - 0.5 * m.l).abs() <= 1e-12 * m.l;
    if (m.rod.inertia - lumped_i).abs() <= 1e-12 * uniform_i.max(1e-300) {
        let di = uniform_i - m.rod.inertia;
        let (mut psi2, mut tq) = (0.0f64, 0.0f64);
        for &p in &phis {
            if let Some(st) = m.state(p) {
                psi2 = psi2.max(st.dpsi[1].abs());
                tq = tq.max((st.dpsi[0] * st.dpsi[1]).abs());
            }
        }
        out.push((
            "rod inertia".into(),
            format!(
                "lumped split: the shaking force is {} for a uniform rod{}; the rod's inertia differs from the uniform bar's by ΔI = {di:.3e} kg·m², which changes the shaking moment by at most |ΔI|ω²·max|ψ''| = {:.4} N·m and the drive torque by at most |ΔI|ω²·max|ψ'ψ''| = {:.4} N·m",
                if centred { "exact" } else { "not exact" },
                if centred { " (the split puts the centroid at L/2)" } else { "" },
                di.abs() * w2 * psi2,
                di.abs() * w2 * tq
            ),
        ));
    } else {
        out.push((
            "rod inertia".into(),
            "modelled (rigid rod with centroid and moment of inertia)".into(),
        ));
    }
    // Series truncation of the kinematics.
    if m.e == 0.0 {
        let mut ex = *m;
        ex.kinematics = Kinematics::Exact;
        let mut th = *m;
        th.kinematics = Kinematics::TwoHarmonic;
        let mut dx = 0.0f64;
        for &p in &phis {
            if let (Some(a), Some(b)) = (ex.state(p), th.state(p)) {
                dx = dx.max((a.x[2] - b.x[2]).abs());
            }
        }
        let bound = (m.slider_mass + m.rod.mass) * w2 * dx;
        let what = if m.kinematics == Kinematics::Exact {
            "exact (nothing left out); the two-harmonic series would change the shaking force by at most"
        } else {
            "two-harmonic: the harmonics of order ≥ 4 left out change the shaking force by at most"
        };
        out.push((
            "kinematics".into(),
            format!(
                "{what} (m3 + m4)ω²·max|x''_exact − x''_2h| = {bound:.4} N ({:.2e} of the headline value; λ = {:.4}, the first term left out is O(λ³))",
                rel(bound, reference),
                m.lambda()
            ),
        ));
    } else {
        out.push((
            "kinematics".into(),
            "exact (an offset slider has no two-harmonic option)".into(),
        ));
    }
    out
}

// ---------------------------------------------------------------------------------------
// Hypocycloid
// ---------------------------------------------------------------------------------------

/// c_k of sqrt(1 − z) = 1 − Σ_k c_k z^k: c_1 = ½, c_{k+1} = c_k (2k − 1)/(2k + 2).
fn binomial_c(k: usize) -> f64 {
    (1..k).fold(0.5, |c, j| {
        c * (2.0 * j as f64 - 1.0) / (2.0 * j as f64 + 2.0)
    })
}

/// Bound T_P on the tail of the paper's series left out at power P:
/// |S/R − (S/R)^(P)| = (1/λ)·Σ_{k>P} c_k z^k ≤ c_{P+1} z_max^{P+1} / (λ (1 − z_max)),
/// z_max = (λ·max|y_A/R|)² (the c_k decrease). Every Fourier coefficient of the tail then
/// has hypot(Δa_i, Δb_i) ≤ 2·T_P. `None` when the mechanism cannot assemble (z_max ≥ 1).
pub fn series_tail_bound(lambda: f64, theta: f64, alpha0: f64, power: usize) -> Option<f64> {
    let ym = max_abs_y(theta, alpha0).ok()?;
    let z = (lambda * ym).powi(2);
    if !(z < 1.0) || lambda <= 0.0 {
        return None;
    }
    Some(binomial_c(power + 1) * z.powi(power as i32 + 1) / (lambda * (1.0 - z)))
}

/// Σ_{i∈K} i²·hypot(Δa_i, Δb_i) between the paper's series of power `power` and the exact
/// coefficients, and |Δa_4|: the residual force (per m_B R ω²) can change by at most the
/// first (triangle inequality), C4 by the second.
pub fn series_change(m: &Hypocycloid, power: usize, orders: &[usize]) -> (f64, f64) {
    let n = orders.iter().copied().max().unwrap_or(0).max(4);
    let c = m.coefficients(n, 64, 1 << 16);
    let (sa, sb) = m.series_coefficients(power, n);
    let force = orders
        .iter()
        .map(|&i| (i * i) as f64 * (sa[i] - c.a[i]).hypot(sb[i] - c.b[i]))
        .sum();
    (force, (sa[4] - c.a[4]).abs())
}

fn hypocycloid(
    h: &crate::families::hypocycloid::file::Resolved,
    reference: &SolveResult,
    headline: f64,
) -> Vec<Effect> {
    let sc = &h.scene;
    let (Some(lambda), Some(theta)) = (
        reference.lookup("design.lambda"),
        reference.lookup("design.theta"),
    ) else {
        return vec![(
            "model limits".into(),
            "the reference has no design (λ, θ): no bound computed".into(),
        )];
    };
    let m = Hypocycloid {
        lambda,
        theta,
        alpha0: sc.alpha0,
    };
    let p = sc.series_power;
    let fscale = sc.m_b * sc.r_carrier * sc.omega * sc.omega;
    let sum_i2: f64 = sc.balance_orders.iter().map(|&i| (i * i) as f64).sum();
    let c4_headline = sc.zero_search.is_some();
    let residual = reference
        .lookup("objectives.residual_force_peak_n")
        .unwrap_or(f64::NAN);
    let mut out = Vec::new();
    // Series truncation.
    if let Some(t) = series_tail_bound(lambda, theta, sc.alpha0, p) {
        let (df, da4) = series_change(&m, p, &sc.balance_orders);
        let z = (lambda * max_abs_y(theta, sc.alpha0).unwrap_or(f64::NAN)).powi(2);
        let head = if c4_headline {
            format!(
                "C4 changes by |Δa4| = {da4:.3e} ≤ 2T = {:.3e} ({:.2e} of the headline C4)",
                2.0 * t,
                rel(2.0 * t, headline)
            )
        } else {
            format!(
                "the residual force peak changes by at most m_B R ω²·Σ_(i∈K) i²·hypot(Δa_i, Δb_i) = {:.4e} N ≤ m_B R ω²·2T·Σ_(i∈K) i² = {:.4e} N ({:.2e} of the headline)",
                fscale * df,
                fscale * 2.0 * t * sum_i2,
                rel(fscale * 2.0 * t * sum_i2, headline)
            )
        };
        let what = match sc.coefficients {
            CoefficientModel::Exact => format!(
                "exact coefficients (nothing left out); the paper's series truncated at z^{p} would leave out"
            ),
            CoefficientModel::Series => format!(
                "the paper's series truncated at z^{p} (model.coefficients = \"series\") leaves out"
            ),
        };
        out.push((
            "series truncation".into(),
            format!(
                "{what} the tail (1/λ)·Σ_(k>{p}) c_k z^k ≤ T = c_{} z_max^{}/(λ(1 − z_max)) = {t:.3e} (z_max = (λ·max|y_A/R|)² = {z:.4}, λ = {lambda:.6}, θ = {theta:.6}); each hypot(Δa_i, Δb_i) ≤ 2T; {head}",
                p + 1,
                p + 1
            ),
        ));
    }
    // Weights against inertia.
    let w = sc.m_b * G;
    let ratio = G / (sc.r_carrier * sc.omega * sc.omega);
    let ds_max = (0..720)
        .map(|k| m.piston(k as f64 * TAU / 720.0).ds.abs())
        .fold(0.0f64, f64::max);
    let c_sum: f64 = sc
        .balance_orders
        .iter()
        .map(|&i| {
            let c = m.coefficients(i, 64, 1 << 16);
            c.a[i].hypot(c.b[i])
        })
        .sum();
    out.push((
        "weights".into(),
        format!(
            "left out (kinematic balancing of the reciprocating mass only): g/(Rω²) = {ratio:.3e}. The weight W = m_B g = {w:.4} N is constant, so it changes no order's force nor the Lanchester pairs; as a frame load it is {:.2e} of the residual force peak {residual:.4e} N. Left out of the drive torque: the pairs' weights, ≤ m_B R g·Σ_(i∈K) C_i = {:.4e} N·m, and, were the cylinder vertical, the piston's, W·R·max|dS/dφ|/R = {:.4e} N·m",
            rel(w, residual),
            sc.m_b * sc.r_carrier * G * c_sum,
            w * sc.r_carrier * ds_max
        ),
    ));
    out.push((
        "other masses, friction".into(),
        "left out, no bound: the scene gives only m_B (no rod, carrier, planet or counter-mass inertias, no friction data), so their effect cannot be computed from it".into(),
    ));
    out
}

// ---------------------------------------------------------------------------------------
// Luffing crane
// ---------------------------------------------------------------------------------------

/// |y_C''| near a head-height extremum at `phi`: the largest three-point second difference
/// (step h/4) centred within h/2 of it; 0 at an end of the range, where an extremum is a
/// sample itself. `None` if a pose fails.
pub fn extremum_curvature(link: &Linkage, phi: f64, h: f64) -> Option<f64> {
    let [p0, p1] = link.phi_range;
    let tol = 1e-9 * (p1 - p0);
    if phi <= p0 + tol || phi >= p1 - tol {
        return Some(0.0);
    }
    let d = 0.25 * h;
    let y = |p: f64| link.pose(p).map(|q| q.c.y);
    let mut k = 0.0f64;
    for c in [phi - 0.5 * h, phi, phi + 0.5 * h] {
        let c = c.clamp(p0 + d, p1 - d);
        k = k.max(((y(c - d)? - 2.0 * y(c)? + y(c + d)?) / (d * d)).abs());
    }
    Some(k)
}

/// Bound on the error of Δh from `n` samples without refinement: an interior extremum at φ*
/// lies within h/2 of a sample, so the sampled extreme is off by at most |y_C''(φ*)|·h²/8;
/// for both, (|y''|_max-pt + |y''|_min-pt)·h²/8, h = (φ_max − φ_min)/n, |y''| from
/// [`extremum_curvature`] at the refined extrema. `None` if the path fails.
pub fn unrefined_path_bound(link: &Linkage, n: usize, xtol: f64) -> Option<f64> {
    let [p0, p1] = link.phi_range;
    let h = (p1 - p0) / n as f64;
    let hh = head_heights(link, n.max(64), xtol).ok()?;
    let k =
        extremum_curvature(link, hh.phi_at_max, h)? + extremum_curvature(link, hh.phi_at_min, h)?;
    Some(k * h * h / 8.0)
}

/// The crane design of a solution, (k1, k2, φ_min, γ1, γ2, γ3) from its `design.*`,
/// evaluated again (linkage and head path) with the scene's settings.
pub fn crane_design(
    c: &crate::families::crane::file::CraneScene,
    result: &SolveResult,
) -> Option<crate::families::crane::synth::Evaluation> {
    let keys = [
        "design.k1",
        "design.k2",
        "design.phi_min_rad",
        "design.gamma1_rad",
        "design.gamma2_rad",
        "design.gamma3_rad",
    ];
    let x: Vec<f64> = keys
        .iter()
        .map(|k| result.lookup(k))
        .collect::<Option<_>>()?;
    crate::families::crane::synth::evaluate(&c.scene, &[x[0], x[1], x[2], x[3], x[4], x[5]], &c.settings).ok()
}

fn crane(c: &crate::families::crane::file::CraneScene, reference: &SolveResult, headline: f64) -> Vec<Effect> {
    let sc = &c.scene;
    let s = &c.settings;
    let ev = crane_design(c, reference);
    let mut out = Vec::new();
    match ev {
        Some(ev) => {
            let link = &ev.synthesis.linkage;
            let n = s.path_samples;
            let tol = s.refine_peaks.then_some(s.xtol);
            let dense = head_heights_with(link, 4 * n, tol).ok();
            let own = head_heights_with(link, n, tol).ok();
            let bound = unrefined_path_bound(link, n, s.xtol);
            match (own, dense, bound) {
                (Some(a), Some(b), Some(bound)) => {
                    out.push((
                        "path sampling".into(),
                        format!(
                            "{n} samples of the luffing range (h = {:.4e} rad), each extremum {}: |Δh(n) − Δh(4n)| = {:.3e} m ({:.2e} of the headline); the refinement error is in `errors.delta_h_m`; unrefined, the two extremes would be off by at most (|y_C''(φ_max-pt)| + |y_C''(φ_min-pt)|)·h²/8 = {bound:.3e} m ({:.2e} of the headline)",
                            (link.phi_range[1] - link.phi_range[0]) / n as f64,
                            if s.refine_peaks { format!("refined by Brent to {:e} rad", s.xtol) } else { "taken at the samples (refine_peaks = false)".into() },
                            (a.delta_h - b.delta_h).abs(),
                            rel((a.delta_h - b.delta_h).abs(), headline),
                            rel(bound, headline)
                        ),
                    ));
                }
                _ => out.push((
                    "path sampling".into(),
                    "the head path of the reference design does not evaluate: no bound".into(),
                )),
            }
        }
        None => out.push((
            "path sampling".into(),
            "the reference design could not be rebuilt: no bound".into(),
        )),
    }
    if let (Some(q), Some(mm)) = (sc.load_mass, reference.lookup("derived.max_load_moment_nm")) {
        out.push((
            "load".into(),
            format!(
                "the rated load Q = {q} kg enters only the unbalanced load moment about A, W·dy_C/dφ, max {mm:.4e} N·m (virtual work, rope of constant length); it does not move the head path of the rigid linkage"
            ),
        ));
    }
    out.push((
        "link masses, elasticity".into(),
        "left out, no bound: the model is geometric (rigid links, no link masses); the scene gives no masses, sections or stiffnesses, so neither the links' weight moment nor the boom/jib deflection under load (which shifts Δh) can be computed from it".into(),
    ));
    out
}

// ---------------------------------------------------------------------------------------
// Eccentric gear
// ---------------------------------------------------------------------------------------

fn mu_at(pair: &GearPair, which: Which, x: f64) -> Option<f64> {
    let ct = pair.contact(x.rem_euclid(TAU));
    match which {
        Which::Mu1 => ct.mu1,
        Which::Mu2 => ct.mu2,
    }
    .map(f64::abs)
}

/// max |µ| at distance `d` from every pole of its own coefficient (both sides), skipping
/// points inside another window of half-width `window` (the same coefficient's other poles,
/// or the 0/0 cusps). With `d = window` this is the largest |µ| on the edges of
/// the working window, which is the peak when the peak is set by the window.
pub fn window_edge_mu(pair: &GearPair, sing: &Singularities, window: f64, d: f64) -> f64 {
    let cusps = sing.singular_cusps();
    let near = |x: f64, c: f64| {
        let t = (x - c).rem_euclid(TAU);
        t.min(TAU - t)
    };
    let inside = |x: f64, p: &Pole| {
        sing.poles
            .iter()
            .filter(|q| q.which == p.which && !std::ptr::eq(*q, p))
            .any(|q| near(x, q.alpha1_rad) < window)
            || cusps.iter().any(|&c| near(x, c) < window)
    };
    let mut best = 0.0f64;
    for p in &sing.poles {
        for x in [p.alpha1_rad - d, p.alpha1_rad + d] {
            if inside(x, p) {
                continue;
            }
            if let Some(v) = mu_at(pair, p.which, x) {
                best = best.max(v);
            }
        }
    }
    best
}

fn gear(g: &crate::families::gear::file::GearProblem, reference: &SolveResult, headline: f64) -> Vec<Effect> {
    let sc = &g.gear;
    let s = &g.settings;
    let mut out = Vec::new();
    let Some(e) = reference.lookup("design.eccentricity_m") else {
        return vec![(
            "pole windows".into(),
            "the reference has no eccentricity: no bound".into(),
        )];
    };
    let an = match crate::families::gear::synth::analyse(sc, e, s) {
        Ok(a) => a,
        Err(err) => {
            return vec![(
                "pole windows".into(),
                format!("the reference design does not analyse ({err}): no bound"),
            )]
        }
    };
    let w = sc.pole_window;
    let cusps = an.sing.singular_cusps();
    let np = an.sing.poles.len();
    let edge = window_edge_mu(&an.pair, &an.sing, w, w);
    let half = window_edge_mu(&an.pair, &an.sing, 0.5 * w, 0.5 * w);
    let count = |wh: Which| an.sing.poles.iter().filter(|p| p.which == wh).count();
    let per = count(Which::Mu1).max(count(Which::Mu2));
    let frac = ((per + cusps.len()) as f64 * 2.0 * w / TAU).min(1.0);
    let set_by = edge >= an.peak.value * (1.0 - 1e-9);
    let designed = if matches!(sc.eccentricity, crate::synth::Var::Free { .. }) {
        format!(
            "; e is designed with the peak |µ| as a constraint, so the window moves e and with it the headline ({headline:.6}): see the pole-window rungs"
        )
    } else {
        String::new()
    };
    out.push((
        "pole windows".into(),
        format!(
            "left out: |α1 − α_pole| < w = {w} rad around each of the {np} poles (and {} 0/0 cusps), at most (max(n_µ1-poles, n_µ2-poles) + n_cusps)·2w/2π = {:.2}% of the α1 range of each coefficient; |µ| → ∞ at a pole, so no window-free peak exists. At the window edges max|µ(α_pole ± w)| = {edge:.6} ({}); with windows of w/2, max|µ(α_pole ± w/2)| = {half:.6} = {:.3}× (|µ| ∝ 1/distance: ≈ 2× when the peak is set by the window); a window narrower by δw raises the peak by ≈ peak·δw/w{designed}",
            cusps.len(),
            100.0 * frac,
            if set_by {
                "= the peak |µ|: it is set by the window".to_string()
            } else {
                format!("< the peak {:.6}: the peak lies inside the working window", an.peak.value)
            },
            half / edge.max(1e-300)
        ),
    ));
    // The windows follow the poles: their location error moves the edges.
    let dmax = reference
        .lookup("derived.max_pole_error_rad")
        .unwrap_or(f64::NAN);
    let slope = if set_by { edge / w } else { 0.0 };
    out.push((
        "pole location".into(),
        format!(
            "each pole is located to ≤ {dmax:.2e} rad; the window edges move with it, changing a peak set by the window by ≈ |µ|/w·δα = {:.2e} ({:.2e} of the peak |µ|)",
            slope * dmax,
            rel(slope * dmax, an.peak.value)
        ),
    ));
    // Closure of the centre distance (trapezoid quadrature): sensitivity by re-analysis.
    let da = an.closure.a_error.abs().max(f64::EPSILON * an.pair.a);
    let step = 1e-7 * an.pair.a;
    let sens = GearPair::new(an.pair.c, sc.generating_radius, an.pair.a + step, sc.omega1)
        .ok()
        .and_then(|p2| {
            let s2 = crate::families::gear::model::singularities(&p2, s.samples_per_arch, s.pole_tol).ok()?;
            let pk = crate::families::gear::model::peak_mu(&p2, &s2, w, s.peak_samples_per_arch, s.peak_xtol)
                .ok()?;
            Some((pk.value - an.peak.value).abs() / step)
        });
    out.push((
        "centre distance".into(),
        match sens {
            Some(k) => format!(
                "a = {:.9} m closes gear 2 to δa = {da:.2e} m (trapezoid closure integral); |∂peak/∂a|·δa = {:.2e} (|∂peak/∂a| = {k:.3e} /m by re-analysis at a + 1e-7·a)",
                an.pair.a,
                k * da
            ),
            None => format!("a = {:.9} m closes gear 2 to δa = {da:.2e} m; the re-analysis at a + 1e-7·a failed: no bound on its effect", an.pair.a),
        },
    ));
    out.push((
        "tooth deflection, backlash, load".into(),
        "left out, no bound: µ is kinematic (rigid teeth, exact cycloidal profiles, no backlash); the scene gives no load, stiffness or tolerance data, so their effect on µ cannot be computed from it".into(),
    ));
    out
}
