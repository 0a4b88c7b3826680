//! Numerical stability on hard cases: dead-centre positions, λ → 1, λ = 1e-8, near-tangent
//! circle intersections, collinear points, µ poles, series at the edge of convergence, mm
//! against m, masses from 1e-6 to 1e6 kg. Each case checks a value from an independent
//! source (a closed form written here, not the library's formula) or a specific error; none
//! may give NaN or panic.

use common::assert_finite;
use cwsynth::families::parse_str;
use cwsynth::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use cwsynth::families::slider_crank::synth::shaking_force;
use cwsynth::families::solve_scene;
use cwsynth::geom::{circle_circle, circumcentre, Side, P2};
use cwsynth::problem::ProblemError;
use cwsynth::report::SolveResult;
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::path::Path;

use crate::common;

const PISTON: &str = include_str!("../problems/piston-1000rpm.toml");
const HYPO: &str = include_str!("../problems/hypocycloid-variant1.toml");
const GEAR: &str = include_str!("../problems/gear-paper-table1.toml");
const CRANE: &str = include_str!("../problems/crane-thesis-example.toml");

fn with(text: &str, replace: &str, by: &str) -> String {
    assert!(text.contains(replace), "fixture lacks `{replace}`");
    text.replacen(replace, by, 1)
}

fn solve_text(text: &str) -> SolveResult {
    let s = parse_str(text, Path::new("hard.toml")).unwrap_or_else(|e| panic!("{e}"));
    let r = solve_scene(&s);
    assert_finite(&r);
    r
}

fn reject(text: &str) -> ProblemError {
    parse_str(text, Path::new("hard.toml")).expect_err("should be rejected")
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// An in-line lumped slider-crank with the given R, L and masses.
fn mech(r: f64, l: f64, m2: f64, m3: f64, m4: f64, split: f64) -> SliderCrank {
    SliderCrank {
        r,
        l,
        e: 0.0,
        kinematics: Kinematics::Exact,
        crank: Crank {
            mass: m2,
            centroid: r / 2.0,
        },
        rod: Rod::lumped(m3, split, l),
        slider_mass: m4,
    }
}

// --- slider-crank --------------------------------------------------------------------------

#[test]
fn dead_centres_match_the_closed_form() {
    // At φ = 0 and φ = π the slider acceleration of the in-line crank is −Rω²(±1 + λ)
    // (textbook), the pin's −Rω²(±1, 0): the shaking force is along the axis only.
    let (r, l, om) = (0.035, 0.14, 100.0);
    let (m2, m3, m4, s) = (0.35, 0.30, 1.03, 0.5);
    let mc = mech(r, l, m2, m3, m4, s);
    let m_rot = m2 * 0.5 + s * m3;
    let m_rec = m4 + (1.0 - s) * m3;
    let lam = r / l;
    for (phi, sign) in [(0.0, 1.0), (PI, -1.0)] {
        let f = shaking_force(&mc, om, P2::zeros(), phi).expect("dead centre is reachable");
        let want = om * om * r * (m_rot * sign + m_rec * (sign + lam));
        assert!(rel(f.x, want) < 1e-12, "φ = {phi}: Fx {} vs {want}", f.x);
        assert!(f.y.abs() < 1e-12 * want.abs(), "φ = {phi}: Fy {}", f.y);
    }
}

#[test]
fn lambda_to_one_is_finite_and_matches_the_closed_form() {
    // (R + |e|)/L = 1 − 1e-6: at φ = π/2 the rod is nearly perpendicular to the axis and the
    // slider acceleration is Rω²·λ/sqrt(1 − λ²) (from x = R cos φ + sqrt(L² − R² sin²φ)).
    let lam: f64 = 1.0 - 1e-6;
    let r = 0.035;
    let l = r / lam;
    let om = 10.0;
    let mc = mech(r, l, 0.0, 0.0, 1.0, 0.5);
    let f = shaking_force(&mc, om, P2::zeros(), FRAC_PI_2).unwrap();
    let want = -om * om * r * lam / (1.0 - lam * lam).sqrt();
    assert!(rel(f.x, want) < 1e-8, "Fx {} vs {want}", f.x);
    // The same through a problem file, solved: finite, optimal, and the optimum is no worse
    // than every baseline.
    let text = with(
        PISTON,
        "rod_length = \"140 mm\"",
        &format!("rod_length = \"{} mm\"", 35.0 / lam),
    );
    let text = with(&text, "rel_tol = 1e-9", "rel_tol = 1e-7");
    let res = solve_text(&text);
    let peak = res.objectives["peak_shaking_force_n"];
    for (b, m) in &res.baselines {
        assert!(
            peak <= m["peak_shaking_force_n"] * (1.0 + 1e-7),
            "optimum {peak} worse than baseline {b}"
        );
    }
    // At the limit itself: a specific error naming the rod length.
    let e = reject(&with(
        PISTON,
        "rod_length = \"140 mm\"",
        "rod_length = \"35 mm\"",
    ));
    assert_eq!(e.field(), Some("mechanism.rod_length"), "{e}");
    assert!(e.to_string().contains("full revolution"), "{e}");
    // An offset that pushes (R + |e|)/L to 1 − 1e-6 is accepted and finite too.
    let text = with(
        PISTON,
        "rod_length = \"140 mm\"",
        &format!(
            "rod_length = \"{} mm\"\noffset = \"5 mm\"",
            40.0 / (1.0 - 1e-6)
        ),
    );
    let res = solve_text(&text);
    assert!(res.objectives["peak_shaking_force_n"] > 0.0);
}

#[test]
fn lambda_1e_minus_8_is_the_first_order_balance() {
    // λ = 1e-8: F = ω²R((m_rot + m_rec) cos φ, m_rot sin φ) + O(λ). A rotating counterweight
    // of size c leaves ((a − c) cos φ, (b − c) sin φ), whose peak max(|a − c|, |b − c|) is
    // least at c = (a + b)/2: peak m_rec Rω²/2, |U| = (m_rot + m_rec/2) R.
    let text = with(
        PISTON,
        "rod_length = \"140 mm\"",
        "rod_length = \"3.5e6 m\"",
    );
    let res = solve_text(&text);
    let (r, om) = (0.035, 1000.0 * TAU / 60.0);
    let m_rot = 0.35 * 0.5 + 0.5 * 0.30;
    let m_rec = 1.03 + 0.5 * 0.30;
    let peak = res.objectives["peak_shaking_force_n"];
    let want = m_rec * r * om * om / 2.0;
    assert!(rel(peak, want) < 1e-6, "peak {peak} vs {want}");
    let u = res.design["counterweight_unbalance_kgm"];
    assert!(rel(u, (m_rot + m_rec / 2.0) * r) < 1e-6, "|U| {u}");
}

#[test]
fn millimetres_and_metres_give_the_same_result() {
    // The same file with every length in m: the results agree to 1e-12 relative.
    let metres = PISTON
        .replace("\"35 mm\"", "\"0.035 m\"")
        .replace("\"140 mm\"", "\"0.14 m\"")
        .replace("\"50 mm\"", "\"0.05 m\"");
    assert_ne!(metres, PISTON);
    let a = solve_text(PISTON);
    let b = solve_text(&metres);
    for (k, va) in &a.objectives {
        let vb = b.objectives[k];
        assert!(
            (va - vb).abs() <= 1e-12 * va.abs().max(1e-300) || va == &vb,
            "objectives.{k}: mm {va} vs m {vb}"
        );
    }
    for (k, va) in &a.design {
        let vb = b.design[k];
        // An angle or a component that should be 0 is compared against the scale.
        let scale = if k.ends_with("_y_kgm") {
            a.design["counterweight_unbalance_kgm"]
        } else {
            va.abs()
        };
        assert!(
            (va - vb).abs() <= 1e-12 * scale,
            "design.{k}: mm {va} vs m {vb}"
        );
    }
}

#[test]
fn masses_from_micrograms_to_kilotonnes_scale_the_forces_linearly() {
    let base = solve_text(PISTON);
    let p0 = base.objectives["peak_shaking_force_n"];
    let u0 = base.design["counterweight_unbalance_kgm"];
    for k in [1e-6, 1e-3, 1e3, 1e6] {
        let mut t = PISTON.to_string();
        for (m, v) in [("0.35", 0.35), ("0.30", 0.30), ("1.03", 1.03)] {
            t = t.replacen(&format!("\"{m} kg\""), &format!("\"{:e} kg\"", v * k), 1);
        }
        t = t.replace(
            "max = \"0.2 kg*m\"",
            &format!("max = \"{:e} kg*m\"", 0.2 * k),
        );
        let r = solve_text(&t);
        let p = r.objectives["peak_shaking_force_n"];
        let u = r.design["counterweight_unbalance_kgm"];
        assert!(rel(p, p0 * k) < 1e-8, "k = {k}: peak {p} vs {}", p0 * k);
        assert!(rel(u, u0 * k) < 1e-6, "k = {k}: |U| {u} vs {}", u0 * k);
    }
}

#[test]
fn zero_and_bad_masses_are_specific_errors() {
    let t = PISTON
        .replace("\"0.35 kg\"", "\"0 kg\"")
        .replace("\"0.30 kg\"", "\"0 kg\"")
        .replace("\"1.03 kg\"", "\"0 kg\"");
    let e = reject(&t);
    assert_eq!(e.field(), Some("mechanism.slider_mass"), "{e}");
    let e = reject(&with(PISTON, "\"1.03 kg\"", "\"-1 kg\""));
    assert_eq!(e.field(), Some("mechanism.slider_mass"), "{e}");
    let e = reject(&with(PISTON, "\"1000 rpm\"", "\"inf rpm\""));
    assert_eq!(e.field(), Some("mechanism.speed"), "{e}");
    let e = reject(&with(PISTON, "\"1000 rpm\"", "nan"));
    assert_eq!(e.field(), Some("mechanism.speed"), "{e}");
}

// --- geometry ------------------------------------------------------------------------------

#[test]
fn near_tangent_circles_in_a_rotated_frame() {
    // Radii 3 and 2 at distance 5 − δ along a 37° direction: the half chord is
    // sqrt((r0+r1−d)(r0+r1+d)(d−r0+r1)(d+r0−r1))/(2d), written here with δ exactly.
    let (r0, r1) = (3.0, 2.0);
    for delta in [1e-6, 1e-9, 1e-12] {
        let d: f64 = 5.0 - delta;
        let delta = 5.0 - d; // exact (Sterbenz)
        let dir = P2::new(37f64.to_radians().cos(), 37f64.to_radians().sin());
        let c0 = P2::new(1.0, -2.0);
        let c1 = c0 + dir * d;
        let p = circle_circle(c0, r0, c1, r1, Side::Left).unwrap();
        let h = (delta * (10.0 - delta) * (d - 1.0) * (d + 1.0)).sqrt() / (2.0 * d);
        let n = P2::new(-dir.y, dir.x);
        let got = (p - c0).dot(&n);
        // The direction vector carries 1e-16 relative rounding: allow that much of d.
        assert!(
            (got - h).abs() <= 1e-12 * h + 4e-16 * d,
            "δ = {delta}: h {got} vs {h}"
        );
        assert!(((p - c0).norm() - r0).abs() < 1e-14 * r0);
    }
    // Just beyond reach: none, never NaN.
    let q = circle_circle(P2::zeros(), 3.0, P2::new(5.0 + 1e-9, 0.0), 2.0, Side::Right);
    assert!(q.is_none());
    // Internally tangent (one circle inside the other, touching).
    let p = circle_circle(P2::zeros(), 3.0, P2::new(1.0, 0.0), 2.0, Side::Left).unwrap();
    assert!((p - P2::new(3.0, 0.0)).norm() < 1e-12, "{p:?}");
}

#[test]
fn collinear_and_nearly_collinear_points() {
    // Exactly collinear: no circle.
    assert!(circumcentre(P2::new(0.0, 0.0), P2::new(1.0, 1.0), P2::new(3.0, 3.0)).is_none());
    // Nearly collinear but resolvable: (−1, 0), (1, 0), (0, ε) have centre (0, (ε² − 1)/(2ε)).
    for eps in [1e-3, 1e-6] {
        let (c, rad) = circumcentre(P2::new(-1.0, 0.0), P2::new(1.0, 0.0), P2::new(0.0, eps))
            .expect("resolvable");
        let cy = (eps * eps - 1.0) / (2.0 * eps);
        assert!(rel(c.y, cy) < 1e-10, "ε = {eps}: {} vs {cy}", c.y);
        assert!(c.x.abs() < 1e-10 * cy.abs());
        assert!(rel(rad, (1.0 + cy * cy).sqrt()) < 1e-10);
    }
    // Below the threshold (1e-12 relative): none, not a centre at 1e15.
    assert!(circumcentre(P2::new(-1.0, 0.0), P2::new(1.0, 0.0), P2::new(0.0, 1e-14)).is_none());
    // Coincident points.
    assert!(circumcentre(P2::zeros(), P2::zeros(), P2::new(1.0, 0.0)).is_none());
}

// --- crane ---------------------------------------------------------------------------------

#[test]
fn crane_degenerate_geometry_is_an_error_not_nan() {
    // Reach limits equal (no luffing range) and inverted: specific errors.
    let e = reject(&with(CRANE, "reach_min = \"10 m\"", "reach_min = \"35 m\""));
    assert!(
        e.field().is_some_and(|f| f.starts_with("mechanism.")),
        "{e}"
    );
    let e = reject(&with(CRANE, "reach_min = \"10 m\"", "reach_min = \"40 m\""));
    assert!(
        e.field().is_some_and(|f| f.starts_with("mechanism.")),
        "{e}"
    );
    // k1 = 0: C2 coincides with C1 (collinear, degenerate triangle): an error or a finite result.
    match parse_str(&with(CRANE, "k1 = 0.2", "k1 = 0"), Path::new("hard.toml")) {
        Err(e) => assert!(e.field().is_some(), "{e}"),
        Ok(s) => assert_finite(&solve_scene(&s)),
    }
    // Near-limit angles: still finite.
    let r = solve_text(&with(CRANE, "gamma2 = \"5 deg\"", "gamma2 = \"1e-9 deg\""));
    assert!(r.objectives["delta_h_m"] >= 0.0);
}

// --- eccentric gear ------------------------------------------------------------------------

#[test]
fn gear_mu_poles_are_excluded_and_finite() {
    // The sliding coefficient µ has poles; the result must report finite peaks over the
    // working window (poles cut out by pole_window), whatever the window.
    for w in ["0.01 rad", "1e-6 rad", "0.1 rad"] {
        let r = solve_text(&with(
            GEAR,
            "pole_window = \"0.01 rad\"",
            &format!("pole_window = \"{w}\""),
        ));
        let mu = r.objectives["peak_sliding_coefficient"];
        assert!(mu.is_finite() && mu > 0.0, "window {w}: {mu}");
    }
    // A window as wide as an arch (π/N) is a specific error.
    let e = reject(&with(
        GEAR,
        "pole_window = \"0.01 rad\"",
        "pole_window = \"0.2 rad\"",
    ));
    assert_eq!(e.field(), Some("model.pole_window"), "{e}");
    // e = 0: a circular pair, constant ratio n1/n2 (independent: R1/R2 of circles = 3).
    let r = solve_text(&with(
        GEAR,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"0 mm\"",
    ));
    let v = r.objectives["ratio_variation"];
    assert!((v - 1.0).abs() < 1e-9, "ratio variation of circles: {v}");
    // e ≥ R: the pitch curve is not a circle around the axis any more: an error naming e.
    let e = reject(&with(
        GEAR,
        "eccentricity = \"15 mm\"",
        "eccentricity = \"37.5 mm\"",
    ));
    assert_eq!(e.field(), Some("design.eccentricity"), "{e}");
}

// --- hypocycloid ---------------------------------------------------------------------------

#[test]
fn hypocycloid_series_at_the_edge_of_convergence() {
    // The root sqrt(1 − λ²y²) converges for λ|y| < 1. λ·max|y| close to 1 (λ = 0.5, θ = 0.5
    // gives a small assembly margin for variant 1): the exact (FFT) coefficients stay finite;
    // beyond the limit the scene is rejected or reported, never NaN.
    for (lam, theta) in [(0.25, 0.5), (0.45, 0.5), (0.6, 0.9)] {
        let t = with(HYPO, "lambda = 0.25", &format!("lambda = {lam}"));
        let t = with(&t, "theta = 0.5", &format!("theta = {theta}"));
        match parse_str(&t, Path::new("hard.toml")) {
            Err(e) => assert!(e.field().is_some(), "λ {lam}: {e}"),
            Ok(s) => {
                let r = solve_scene(&s);
                assert_finite(&r);
            }
        }
    }
    // λ = 1e-8: the rod is infinitely long, the motion is pure harmonic of the hypocycloid
    // line: the residual force after balancing orders 1–3 vanishes (to the λ-order left).
    let t = with(HYPO, "lambda = 0.25", "lambda = 1e-8");
    let r = solve_text(&t);
    let res = r.objectives["residual_force_peak_n"];
    let unb = r.objectives["unbalanced_force_peak_n"];
    assert!(res <= 1e-6 * unb, "residual {res} of {unb}");
    // Higher series power never gives NaN.
    for p in [1, 6, 12] {
        let t = with(HYPO, "series_power = 3", &format!("series_power = {p}"));
        match parse_str(&t, Path::new("hard.toml")) {
            Err(e) => assert_eq!(e.field(), Some("model.series_power"), "{e}"),
            Ok(s) => assert_finite(&solve_scene(&s)),
        }
    }
}

#[test]
fn loose_rel_tol_solves_without_panic() {
    // Regression: rel_tol in (1e-6, 1) is allowed by [accuracy], but the exchange loop
    // clamped its next tolerance with `clamp(rel_tol, 1e-6)`, which panics for min > max.
    // Found by `cwsynth study` (its `rel_tol 1e-3` rung). The loose optimum is within
    // rel_tol of the tight one.
    let tight = solve_text(PISTON).objectives["peak_shaking_force_n"];
    for t in ["1e-3", "1e-6", "0.5"] {
        let r = solve_text(&with(PISTON, "rel_tol = 1e-9", &format!("rel_tol = {t}")));
        let p = r.objectives["peak_shaking_force_n"];
        let tol: f64 = t.parse().unwrap();
        assert!(
            p >= tight * (1.0 - 1e-9) && p <= tight * (1.0 + 2.0 * tol),
            "rel_tol {t}: {p} vs {tight}"
        );
    }
}

/// A flat direction of the optimum (issue 37): the six-bar press with a third counterweight, on
/// its coupler, which buys nothing — the optimum is a whole set of designs, and the polish's
/// Newton system is rank-deficient there (it ended `inaccurate` after 30 exchange rounds and
/// 1,227 interior-point iterations before the minimum-norm step). Now `optimal` in a few
/// rounds, its peak the two-counterweight optimum of the shipped file (more freedom, the
/// same value) within the two stated errors.
#[test]
fn a_counterweight_that_buys_nothing_still_certifies() {
    let two = include_str!("../problems/linkage-sixbar-press.toml");
    let two = with(two, "pareto_points = 20", "pareto_points = 0");
    let three = with(
        &two,
        "[[design.counterweights]]\nlink = \"rocker\"",
        "[[design.counterweights]]\nlink = \"coupler\"\nmass = { min = \"0 kg\", max = \"10 kg\" }\nradius = \"80 mm\"\n\n[[design.counterweights]]\nlink = \"rocker\"",
    );
    let (a, b) = (solve_text(&two), solve_text(&three));
    for r in [&a, &b] {
        assert_eq!(
            r.status,
            cwsynth::report::Status::Optimal,
            "{:?}",
            r.warnings
        );
    }
    let key = "peak_shaking_force_n";
    let (fa, fb) = (a.objectives[key], b.objectives[key]);
    assert!(
        (fa - fb).abs() <= a.errors[key] + b.errors[key],
        "{fa} against {fb}"
    );
    assert!(
        b.derived["socp_rounds"] <= 10.0,
        "{}",
        b.derived["socp_rounds"]
    );
    // The optimum is a set of designs: the one shown is its lightest (issue 37), 9.63 kg
    // where the exchange loop's point weighed 18.74 kg, and the report says so.
    let mass = "counterweight_mass_kg";
    assert!(b.objectives[mass] < 10.0, "{}", b.objectives[mass]);
    assert!(
        b.warnings
            .iter()
            .any(|w| w.contains("the optimum is not unique")),
        "{:?}",
        b.warnings
    );
    // The second program is the mass goal under the optimum's peak. The same scene asked
    // for its lightest counterweights with the peak force limited to b's, from a cold start,
    // finds b's mass to 1e-4. That path ends `inaccurate` here: its exchange loop leaves the
    // limit 8.8e-7 N short, and the mass falls by about 216 kg per N of the limit (measured
    // between 70.0843 and 70.085 N), so it is expected a little lighter than b, not equal.
    let by_mass = with(
        &three,
        "minimize = \"peak-force\"",
        &format!("minimize = \"counterweight-mass\"\nmax_peak_force = \"{fb} N\""),
    );
    let c = solve_text(&by_mass);
    let (mb, mc) = (b.objectives[mass], c.objectives[mass]);
    assert!((mc - mb).abs() <= 1e-4 * mb, "{mc} against {mb}");
}

#[test]
fn a_unique_optimum_keeps_its_design() {
    // The two-counterweight six-bar's optimum is isolated: no second program, no note.
    let two = include_str!("../problems/linkage-sixbar-press.toml");
    let a = solve_text(&with(two, "pareto_points = 20", "pareto_points = 0"));
    assert!(
        !a.warnings.iter().any(|w| w.contains("not unique")),
        "{:?}",
        a.warnings
    );
}
