//! Tests of the eccentric cycloidal gear pair (issue 6) against independent references:
//! closed forms (e = 0), an independent quadrature, finite-difference tooth profiles,
//! brute-force scans and the paper's Table 1.

use cwsynth::families::gear::model::*;
use cwsynth::families::gear::synth::*;
use cwsynth::geom::{circumcentre, cross, P2};
use std::f64::consts::{PI, TAU};

const R: f64 = 37.5e-3;
const RG: f64 = 1.25e-3;

fn pair(e: f64) -> GearPair {
    let c = EccentricCircle::new(R, e).unwrap();
    let cl = closing_center_distance(&c, 3, 1).unwrap();
    GearPair::new(c, RG, cl.a, 15.0).unwrap()
}

/// Closure integral by composite Simpson in the central angle θ (a different variable and
/// rule from the library's trapezoid in α1): dα1/dθ = R(R + e cos θ)/ρ², ρ² = R² + e² + 2eR cos θ.
fn closure_simpson(r: f64, e: f64, a: f64, n: usize) -> f64 {
    let h = TAU / n as f64;
    let f = |t: f64| {
        let rho = (r * r + e * e + 2.0 * e * r * t.cos()).sqrt();
        rho / (a - rho) * r * (r + e * t.cos()) / (rho * rho)
    };
    let mut s = f(0.0) + f(TAU);
    for k in 1..n {
        s += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

#[test]
fn circular_pair_has_constant_mu_per_arch_in_closed_form() {
    // e = 0: a = R(1 + n1/n2) and, on an arch with σ = ±1,
    // µ1 = 2ra/(ρ2(σρ1 + 2r)), µ2 = −µ1/(1 − µ1), independent of ϕ.
    let p = pair(0.0);
    assert!((p.a - 4.0 * R).abs() < 1e-15, "a = {}", p.a);
    let (r1, r2) = (R, 3.0 * R);
    for i in 0..p.n_arches {
        let sigma = if i % 2 == 0 { 1.0 } else { -1.0 };
        let mu1 = 2.0 * RG * p.a / (r2 * (sigma * r1 + 2.0 * RG));
        let mu2 = -mu1 / (1.0 - mu1);
        let (a0, a1) = (p.arch_start(i), p.arch_start(i + 1));
        for k in 1..20 {
            let x = a0 + (a1 - a0) * k as f64 / 20.0;
            let ct = p.contact(x);
            assert_eq!(ct.arch, i);
            assert!(
                (ct.mu1.unwrap() - mu1).abs() < 1e-13,
                "arch {i}: {} vs {mu1}",
                ct.mu1.unwrap()
            );
            assert!((ct.mu2.unwrap() - mu2).abs() < 1e-13);
        }
    }
    // No poles; every cusp has ψ = 0 and is the 0/0 point; µ is None there, never NaN.
    let s = singularities(&p, 24, 1e-13).unwrap();
    assert!(s.poles.is_empty());
    assert_eq!(s.zeros.len(), p.n_arches);
    assert!(s.zeros.iter().all(|z| z.kind == ZeroKind::Indeterminate));
    let ct = p.contact(p.arch_start(3));
    assert!(ct.mu1.is_none() && ct.mu2.is_none());
}

#[test]
fn normal_velocities_agree_at_contact_and_normal_is_the_profile_normal() {
    let p = pair(15e-3);
    let a2 = Alpha2Map::new(&p.c, p.a);
    let o2 = P2::new(p.a, 0.0);
    let rot = |v: P2, ang: f64| {
        let (s, c) = ang.sin_cos();
        P2::new(c * v.x - s * v.y, s * v.x + c * v.y)
    };
    // K in gear 1's frame (gear turned by −α1) and in gear 2's frame (turned by α2).
    let k1 = |x: f64, arch: usize| rot(p.contact_on(x, arch).k, x);
    let k2 = |x: f64, arch: usize| rot(p.contact_on(x, arch).k - o2, -a2.alpha2(x));
    let mut worst_conj: f64 = 0.0;
    let mut worst_fd: f64 = 0.0;
    for k in 0..997 {
        let x = TAU * (k as f64 + 0.37) / 997.0;
        let ct = p.contact(x);
        let vn1 = ct.v1.dot(&ct.d);
        let vn2 = ct.v2.dot(&ct.d);
        worst_conj = worst_conj.max((vn1 - vn2).abs() / ct.v1.norm());
        // Sliding velocity: |V1 − V2| equals the closed form and is tangential.
        let dv = ct.v1 - ct.v2;
        assert!((dv.norm() - ct.v_slide.abs()).abs() < 1e-12 * ct.v1.norm());
        // Tooth-profile tangents by central differences of the contact locus in each
        // gear's own frame, rotated back to the fixed frame: both ⟂ d.
        if ct.phi < 0.05 || ct.phi > TAU - 0.05 {
            continue; // cusps: the profile tangent turns over there
        }
        let h = 1e-6;
        let t1 = rot(k1(x + h, ct.arch) - k1(x - h, ct.arch), -x);
        let t2 = rot(k2(x + h, ct.arch) - k2(x - h, ct.arch), a2.alpha2(x));
        worst_fd = worst_fd
            .max((t1.dot(&ct.d) / t1.norm()).abs())
            .max((t2.dot(&ct.d) / t2.norm()).abs());
        // And the contact point lies on the generating circle (centre at distance R + σr from C, in gear 1's frame).
        let th = p.c.theta_of_alpha(x);
        let g = P2::new(15e-3, 0.0) + P2::new(th.cos(), th.sin()) * (R + ct.sigma * RG);
        assert!(
            ((k1(x, ct.arch) - g).norm() - RG).abs() < 1e-15,
            "K off the generating circle"
        );
    }
    assert!(
        worst_conj < 1e-13,
        "normal velocities differ by {worst_conj:e} (relative)"
    );
    assert!(worst_fd < 1e-6, "profile normal off by {worst_fd:e}");
}

#[test]
fn closure_matches_independent_quadrature_and_paper() {
    for e in [0.0, 5e-3, 15e-3, 30e-3] {
        let c = EccentricCircle::new(R, e).unwrap();
        let cl = closing_center_distance(&c, 3, 1).unwrap();
        let j = closure_simpson(R, e, cl.a, 4000);
        assert!((j - TAU / 3.0).abs() < 1e-11, "e = {e}: J = {j}");
        assert!(cl.a_error < 1e-13);
    }
    // Paper: a12 = 148 mm is the closing distance rounded to 0.1 mm.
    let p = pair(15e-3);
    assert!((p.a - 0.148).abs() < 0.05e-3, "a = {}", p.a);
    let j148 = closure_simpson(R, 15e-3, 0.148, 4000);
    let q = closure_integral(&p.c, 0.148, 1e-15);
    assert!((q.value - j148).abs() < 1e-12);
    // Gear 2 turns 2π n2/n1 per turn of gear 1.
    let a2 = Alpha2Map::new(&p.c, p.a);
    assert!((a2.alpha2(TAU) - TAU / 3.0).abs() < 1e-13);
    // α2 at intermediate angles against Simpson of the same integrand in θ.
    for x in [0.3, 1.7, 4.0] {
        let th = p.c.theta_of_alpha(x);
        let n = 2000;
        let h = th / n as f64;
        let f = |t: f64| {
            let rho = (R * R + 225e-6 + 2.0 * 15e-3 * R * t.cos()).sqrt();
            rho / (p.a - rho) * R * (R + 15e-3 * t.cos()) / (rho * rho)
        };
        let mut s = f(0.0) + f(th);
        for k in 1..n {
            s += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        assert!((a2.alpha2(x) - s * h / 3.0).abs() < 1e-12, "α2({x})");
    }
}

#[test]
fn pitch_curves_lie_on_their_circle_and_gear2_closes() {
    let out = solve(&paper_table1(), &Settings::default()).unwrap();
    let pc = &out.pitch_curves;
    for q in &pc.gear1_m {
        let d = (q[0] - 15e-3).hypot(q[1]);
        assert!(
            (d - R).abs() < 1e-16 * 4.0,
            "point off the circle by {}",
            d - R
        );
    }
    // Gear 2's polygon perimeter (a different computation) vs the derived perimeter, and
    // both vs (n1/n2)·2πR (the pitch curves roll without slip).
    let g2 = &pc.gear2_m;
    let mut per = 0.0;
    for k in 0..g2.len() {
        let (a, b) = (g2[k], g2[(k + 1) % g2.len()]);
        per += (b[0] - a[0]).hypot(b[1] - a[1]);
    }
    let d = out.derived.gear2_perimeter_m;
    assert!((d - 3.0 * TAU * R).abs() < 1e-12, "{d}");
    assert!((per - d).abs() < 2e-5 * d, "polygon {per} vs {d}");
    // The curves touch at P = (ρ1(0), 0) = (R + e, 0) at α1 = 0.
    assert!(
        (pc.gear1_m[0][0] - 52.5e-3).abs() < 1e-15 && (pc.gear2_m[0][0] - 52.5e-3).abs() < 1e-15
    );
}

#[test]
fn obliquity_ratio_range_and_theta_map() {
    let p = pair(15e-3);
    let mut psi_max: f64 = 0.0;
    let (mut imin, mut imax) = (f64::INFINITY, 0.0f64);
    for k in 0..3600 {
        let x = TAU * k as f64 / 3600.0;
        let h = 1e-6;
        let fd = (p.c.rho1(x + h) - p.c.rho1(x - h)) / (2.0 * h) / p.c.rho1(x);
        let (s, c) = p.c.psi_sin_cos(x);
        assert!((fd - s / c).abs() < 1e-8, "tan ψ at {x}");
        assert!((s.hypot(c) - 1.0).abs() < 1e-15);
        psi_max = psi_max.max(s.abs().asin());
        imin = imin.min(p.i12(x));
        imax = imax.max(p.i12(x));
        // θ ↔ α1 round trip, and the pitch point is on the circle at central angle θ.
        let th = p.c.theta_of_alpha(x);
        assert!((p.c.alpha_of_theta(th) - x).abs() < 1e-14);
        let q = p.c.point(x) - P2::new(15e-3, 0.0);
        assert!((q - P2::new(th.cos(), th.sin()) * R).norm() < 1e-16 * 8.0);
    }
    // Sampled maxima on a grid containing α1 = 0, π/2, π.
    assert!((psi_max - (0.4f64).asin()).abs() < 1e-15);
    let (lo, hi) = p.ratio_range();
    assert!((imin - lo).abs() < 1e-14 && (imax - hi).abs() < 1e-13);
}

#[test]
fn poles_match_brute_force_scan_and_are_real_poles() {
    let p = pair(15e-3);
    let s = singularities(&p, 24, 1e-13).unwrap();
    // Brute force: sign changes of v_t1, v_t2 on a uniform grid over the cycle, skipping
    // the cusps where the arch (and with it the sign of d) changes.
    let n = 200_000;
    let mut found = [Vec::new(), Vec::new()];
    let mut prev = p.contact(0.0);
    for k in 1..=n {
        let x = TAU * k as f64 / n as f64;
        let ct = p.contact(x);
        if ct.arch == prev.arch && k < n {
            if prev.vt1 * ct.vt1 < 0.0 {
                found[0].push(x);
            }
            if prev.vt2 * ct.vt2 < 0.0 {
                found[1].push(x);
            }
        }
        prev = ct;
    }
    for (w, list) in [(Which::Mu1, &found[0]), (Which::Mu2, &found[1])] {
        let mine: Vec<&Pole> = s.poles.iter().filter(|p| p.which == w).collect();
        assert_eq!(mine.len(), list.len(), "{w:?}");
        for (a, b) in mine.iter().zip(list.iter()) {
            assert!(
                (a.alpha1_rad - b).abs() < TAU / n as f64,
                "{w:?}: {} vs {b}",
                a.alpha1_rad
            );
        }
    }
    // Every pole is a sign change of µ through ±∞, located to 1e-12 rad.
    for pole in &s.poles {
        assert!(pole.error_rad <= 1e-12);
        let mu = |x: f64| {
            let ct = p.contact_on(x, pole.arch);
            match pole.which {
                Which::Mu1 => ct.mu1.unwrap(),
                Which::Mu2 => ct.mu2.unwrap(),
            }
        };
        let (l, r) = (mu(pole.alpha1_rad - 1e-9), mu(pole.alpha1_rad + 1e-9));
        assert!(
            l * r < 0.0 && l.abs() > 1e4 && r.abs() > 1e4,
            "{pole:?}: {l} {r}"
        );
    }
    // Zeros: K = P exactly there and µ = 0, except at ψ = 0 (α1 = 0, π) where it is 0/0.
    for z in &s.zeros {
        let ct = p.contact_on(z.alpha1_rad, z.arch);
        assert!((ct.k - ct.p).norm() < 1e-16 * 8.0);
        match z.kind {
            ZeroKind::PitchPoint => {
                assert!(ct.mu1.unwrap().abs() < 1e-12 && ct.mu2.unwrap().abs() < 1e-12)
            }
            ZeroKind::Indeterminate => {
                assert!(z.alpha1_rad.abs() < 1e-12 || (z.alpha1_rad - PI).abs() < 1e-12)
            }
        }
    }
    assert_eq!(
        s.zeros
            .iter()
            .filter(|z| z.kind == ZeroKind::Indeterminate)
            .count(),
        2
    );
}

#[test]
fn gear2_curvature_matches_discrete_circumcircles() {
    for e in [15e-3, 28e-3] {
        let p = pair(e);
        let a2 = Alpha2Map::new(&p.c, p.a);
        let o2 = P2::new(p.a, 0.0);
        let pt = |x: f64| {
            let ang = PI - a2.alpha2(x);
            o2 + P2::new(ang.cos(), ang.sin()) * (p.a - p.c.rho1(x))
        };
        for k in 0..50 {
            let x = TAU * (k as f64 + 0.5) / 50.0;
            let h = 1e-4;
            let (a, b, c) = (pt(x - h), pt(x), pt(x + h));
            let kappa = p.gear2_curvature(x);
            match circumcentre(a, b, c) {
                Some((_, rc)) => {
                    // Gear 2's curve is traversed clockwise in the fixed frame (α2 grows, π − α2 falls).
                    let sign = -cross(b - a, c - b).signum();
                    assert!(
                        (sign / rc - kappa).abs() < 1e-5 * kappa.abs().max(1.0),
                        "e = {e}, α1 = {x}: {} vs {kappa}",
                        sign / rc
                    );
                }
                None => assert!(kappa.abs() < 1e-3),
            }
        }
    }
}

#[test]
fn convexity_is_lost_at_a_critical_eccentricity() {
    let kmin = |e: f64| min_gear2_curvature(&pair(e), 720).unwrap().0;
    assert!(kmin(15e-3) > 0.0);
    let ec = cwsynth::numeric::brent_root(kmin, 15e-3, 36e-3, 1e-12)
        .unwrap()
        .x;
    assert!(kmin(36e-3) < 0.0);
    // Independent: just beyond e_c, the discrete gear-2 polygon turns the other way
    // somewhere; just before, it never does.
    let turns_back = |e: f64| {
        let p = pair(e);
        let out = pitch_curves(&p, &Alpha2Map::new(&p.c, p.a), 3.0, 20_000);
        let g = out.gear2_m;
        let m = g.len();
        (0..m).any(|k| {
            let (a, b, c) = (g[k], g[(k + 1) % m], g[(k + 2) % m]);
            cross(
                P2::new(b[0] - a[0], b[1] - a[1]),
                P2::new(c[0] - b[0], c[1] - b[1]),
            ) > 0.0
        })
    };
    assert!(!turns_back(ec * 0.99));
    assert!(turns_back(ec * 1.01));
}

#[test]
fn paper_table1_outcome() {
    let out = solve(&paper_table1(), &Settings::default()).unwrap();
    assert_eq!(out.status, Status::Analysed);
    assert_eq!(out.design.eccentricity_m, 15e-3);
    // Closed-form ratio range with the closing a.
    let a = out.derived.center_distance_m;
    assert!((out.derived.ratio_min - (a - 52.5e-3) / 52.5e-3).abs() < 1e-14);
    assert!((out.derived.ratio_max - (a - 22.5e-3) / 22.5e-3).abs() < 1e-13);
    // Table inconsistencies are reported: 15 teeth, not 12; 45 on gear 2, not 36.
    assert_eq!(out.derived.teeth_gear1, 15.0);
    assert_eq!(out.derived.teeth_gear2, 45.0);
    assert!(out
        .warnings
        .iter()
        .any(|w| w.starts_with("mechanism.teeth_gear1")));
    assert!(out
        .warnings
        .iter()
        .any(|w| w.starts_with("mechanism.center_distance")));
    let ca = out
        .paper
        .iter()
        .find(|c| c.quantity.starts_with("centre distance"))
        .unwrap();
    assert_eq!(ca.paper, 0.148);
    assert!((ca.computed.unwrap() - 0.148).abs() < 0.05e-3);
    // Paper's symmetry claim: µ2 = −µ1/(1 − µ1) exactly, checked on the series.
    for (m1, m2) in out.series.mu1.iter().zip(&out.series.mu2) {
        if let (Some(m1), Some(m2)) = (m1, m2) {
            assert!((m2 + m1 / (1.0 - m1)).abs() < 1e-12 * (1.0 + m2.abs()));
        }
    }
    // Series exclude the pole windows and contain no NaN.
    for pole in &out.poles {
        for (k, x) in out.series.alpha1_rad.iter().enumerate() {
            let d = (x - pole.alpha1_rad).rem_euclid(TAU);
            if d.min(TAU - d) < out.derived.pole_window_rad {
                let v = if pole.which == Which::Mu1 {
                    out.series.mu1[k]
                } else {
                    out.series.mu2[k]
                };
                assert!(v.is_none());
            }
        }
    }
    // The peak is ≥ every plotted |µ| (plotted points are a subset of the working window).
    let peak = out.objectives.peak_sliding_coefficient;
    let plotted = out
        .series
        .mu1
        .iter()
        .chain(&out.series.mu2)
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        peak + out.errors.peak_sliding_coefficient >= plotted,
        "{peak} < {plotted}"
    );
    assert!(out.errors.peak_sliding_coefficient < 1e-6);
}

#[test]
fn json_contract_keys() {
    let out = solve(&paper_table1(), &Settings::default()).unwrap();
    let v = serde_json::to_value(&out).unwrap();
    assert!(v["design"]["eccentricity_m"].is_f64());
    for k in ["center_distance_m", "ratio_min", "ratio_max"] {
        assert!(v["derived"][k].is_f64(), "{k}");
    }
    assert!(v["objectives"]["peak_sliding_coefficient"].is_f64());
    let obj: Vec<&String> = v["objectives"].as_object().unwrap().keys().collect();
    let err: Vec<&String> = v["errors"].as_object().unwrap().keys().collect();
    assert_eq!(obj, err);
    for m in ["objectives", "errors", "derived", "design"] {
        assert!(
            v[m].as_object().unwrap().values().all(|x| x.is_f64()),
            "{m} has a non-number"
        );
    }
    let poles = v["poles"].as_array().unwrap();
    assert!(!poles.is_empty());
    for p in poles {
        assert!(p["alpha1_rad"].is_f64());
        assert!(p["which"] == "mu1" || p["which"] == "mu2");
    }
    assert!(v["zeros"]
        .as_array()
        .unwrap()
        .iter()
        .all(|z| z["kind"] == "pitch_point" || z["kind"] == "indeterminate"));
}

#[test]
fn eccentricity_near_and_beyond_r() {
    let s = Settings {
        series_points: 64,
        curve_points: 64,
        ..Settings::default()
    };
    // e ≥ R, NaN, negative: a clear error naming the field.
    for e in [R, 1.2 * R, f64::NAN, -1e-3] {
        let sc = GearScene {
            eccentricity: Var::Fixed(e),
            ..paper_table1()
        };
        match solve(&sc, &s) {
            Err(SolveError::Field(f)) => assert_eq!(f.field, "design.eccentricity"),
            other => panic!("e = {e}: {other:?}"),
        }
    }
    let sc = GearScene {
        eccentricity: Var::Free { min: 0.0, max: R },
        ..paper_table1()
    };
    assert!(matches!(solve(&sc, &s), Err(SolveError::Field(_))));
    assert!(matches!(
        EccentricCircle::new(R, R),
        Err(GearError::PivotOutside { .. })
    ));
    // e → R: an answer with warnings, every number finite.
    let sc = GearScene {
        eccentricity: Var::Fixed(0.99 * R),
        ..paper_table1()
    };
    let out = solve(&sc, &s).unwrap();
    assert!(out.warnings.iter().any(|w| w.contains("close to 1")));
    assert!(out.warnings.iter().any(|w| w.contains("≤ 2r")));
    let a = out.derived.center_distance_m;
    assert!(
        (out.derived.ratio_max - (a - 0.01 * R) / (0.01 * R)).abs() < 1e-9 * out.derived.ratio_max
    );
    assert!(cwsynth::report::number_map(&out.objectives)
        .values()
        .chain(cwsynth::report::number_map(&out.derived).values())
        .all(|x| x.is_finite()));
    let j = closure_simpson(R, 0.99 * R, a, 200_000);
    assert!((j - TAU / 3.0).abs() < 1e-8, "{j}");
}

#[test]
fn bad_fields_are_named() {
    let key = |sc: GearScene| match sc.validate() {
        Err(f) => f.field,
        Ok(()) => "ok".into(),
    };
    assert_eq!(
        key(GearScene {
            generating_radius: 1.3e-3,
            ..paper_table1()
        }),
        "mechanism.generating_radius"
    );
    assert_eq!(
        key(GearScene {
            pitch_radius: -1.0,
            ..paper_table1()
        }),
        "mechanism.pitch_radius"
    );
    assert_eq!(
        key(GearScene {
            omega1: 0.0,
            ..paper_table1()
        }),
        "mechanism.speed"
    );
    assert_eq!(
        key(GearScene {
            turns_gear2: 0,
            ..paper_table1()
        }),
        "mechanism.turns_gear2"
    );
    assert_eq!(
        key(GearScene {
            pole_window: 1.0,
            ..paper_table1()
        }),
        "model.pole_window"
    );
    assert_eq!(key(paper_table1()), "ok");
}

#[test]
fn scale_invariance() {
    // Lengths ×1000: µ, i12, poles are dimensionless and must not change.
    let base = pair(15e-3);
    let big = {
        let c = EccentricCircle::new(R * 1e3, 15.0).unwrap();
        let cl = closing_center_distance(&c, 3, 1).unwrap();
        GearPair::new(c, RG * 1e3, cl.a, 15.0).unwrap()
    };
    assert!((big.a / base.a - 1e3).abs() < 1e-11);
    let s1 = singularities(&base, 24, 1e-13).unwrap();
    let s2 = singularities(&big, 24, 1e-13).unwrap();
    assert_eq!(s1.poles.len(), s2.poles.len());
    for (a, b) in s1.poles.iter().zip(&s2.poles) {
        assert!((a.alpha1_rad - b.alpha1_rad).abs() < 1e-11);
    }
    for k in 0..100 {
        let x = TAU * (k as f64 + 0.5) / 100.0;
        let (c1, c2) = (base.contact(x), big.contact(x));
        if let (Some(m1), Some(m2)) = (c1.mu1, c2.mu1) {
            assert!((m1 - m2).abs() < 1e-9 * (1.0 + m1.abs()));
        }
    }
}

#[test]
fn eccentricity_design_matches_brute_force_sweep() {
    let sc = paper_table1_design();
    let st = Settings {
        series_points: 64,
        curve_points: 64,
        sweep_points: 13,
        ..Settings::default()
    };
    let out = solve(&sc, &st).unwrap();
    let e_star = out.design.eccentricity_m;
    // Brute force: the largest feasible e on a fine grid (ratio variation grows with e).
    let fine = 121;
    let mut best: f64 = 0.0;
    let mut prev_var = 0.0;
    for k in 0..fine {
        let e = 30e-3 * k as f64 / (fine - 1) as f64;
        let an = analyse(&sc, e, &st).unwrap();
        assert!(an.ratio_variation() >= prev_var);
        prev_var = an.ratio_variation();
        let ok =
            an.peak.value <= 0.6 && an.curvature.0 > 0.0 && (e / R).asin() <= 30f64.to_radians();
        if ok {
            best = e;
        }
    }
    assert!(
        e_star >= best && e_star < best + 30e-3 / (fine - 1) as f64,
        "design {e_star} vs brute force {best}"
    );
    assert!(matches!(
        out.status,
        Status::ConstraintBound | Status::Optimal | Status::AtBound
    ));
    assert!(!out.sweep.is_empty());
}
