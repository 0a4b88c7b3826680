//! Issue 34: the RMS near a fold. A crank-rocker 1 µm from its change point (crank 40,
//! coupler 100, rocker 60.001, frame 120 mm: s + l = p + q − 1 µm) has a shaking force that
//! is a spike a few milliradians wide where coupler and rocker nearly stretch out; 360
//! uniform angles gave RMS 108.4 N and another design. The engine now doubles the count
//! until the mean-square form converges, and its stated error bounds the quadrature over the
//! whole design box. Checked here against an independent quadrature (adaptive Simpson to
//! 1e-3 N²·rad, ~3e-8 relative, above the field's round-off) of the same field: the design's true RMS and the exact optimum (R² is quadratic in
//! the crank counterweight's first moment u: six evaluations give it exactly) both lie
//! within the stated error.

use crate::common::with;
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::linkage::synth::{field_objects, SceneFields};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::report::Status;
use cwsynth::synth::minimax::{AffineField, AffineValue};
use std::f64::consts::TAU;
use std::path::Path;

pub(crate) const NEAR_FOLD: &str = r#"
name = "fourbar-near-fold"
family = "linkage"

[mechanism]
speed = "300 rpm"
crank_length = "40 mm"

[[mechanism.dyads]]
kind = "RRR"
links = ["coupler", "rocker"]
p = "crank.tip"
length1 = "100 mm"
q = ["120 mm", "0 mm"]
length2 = "60.001 mm"
branch = "left"

[mechanism.links.crank]
mass = "0.2 kg"
uniform_bar = true

[mechanism.links.coupler]
mass = "0.6 kg"
uniform_bar = true

[mechanism.links.rocker]
mass = "0.4 kg"
uniform_bar = true

[[design.counterweights]]
link = "crank"
mass = { min = "0 kg", max = "2 kg" }
radius = "60 mm"

[objective]
minimize = "rms-force"
"#;

/// ∫ f over [a, b] by adaptive Simpson to `tol` (absolute), depth-limited.
fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    fn step(
        f: &dyn Fn(f64) -> f64,
        a: f64,
        b: f64,
        fa: f64,
        fm: f64,
        fb: f64,
        whole: f64,
        tol: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (a + b);
        let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
        let (flm, frm) = (f(lm), f(rm));
        let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
        let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
        if depth == 0 || (left + right - whole).abs() <= 15.0 * tol {
            return left + right + (left + right - whole) / 15.0;
        }
        step(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1)
            + step(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1)
    }
    // Start from 64 panels so the spike cannot hide between the first points.
    let n = 64;
    let h = (b - a) / n as f64;
    (0..n)
        .map(|k| {
            let (x0, x1) = (a + k as f64 * h, a + (k + 1) as f64 * h);
            let (f0, fm, f1) = (f(x0), f(0.5 * (x0 + x1)), f(x1));
            step(
                f,
                x0,
                x1,
                f0,
                fm,
                f1,
                h / 6.0 * (f0 + 4.0 * fm + f1),
                tol / n as f64,
                40,
            )
        })
        .sum()
}

/// The true RMS of the shaking force of `text`'s linkage with the crank counterweight's
/// first moment u (its mass and inertia do not move the force of a frame pivot).
fn true_rms(text: &str) -> impl Fn([f64; 2]) -> f64 {
    let sc = parse_str(text, Path::new("near-fold.toml")).unwrap();
    let p: LinkageProblem = sc.machine::<LinkageProblem>().unwrap().clone();
    move |u: [f64; 2]| {
        let fields = SceneFields::new(&p.scene);
        let (force, _, _) = field_objects(&fields, "");
        let x = [1.0, u[0], u[1], 1e-3];
        let sq = |theta: f64| {
            let mut v = AffineValue::zeros(4);
            force.eval(theta, &mut v);
            v.magnitude(force.dim(), &x).powi(2)
        };
        (simpson(&sq, 0.0, TAU, 1e-3) / TAU).sqrt()
    }
}

#[test]
fn the_rms_near_a_fold_and_its_optimum_lie_within_the_stated_error() {
    let r = solve_scene(&parse_str(NEAR_FOLD, Path::new("near-fold.toml")).unwrap());
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let key = "rms_shaking_force_n";
    let (v, err) = (r.objectives[key], r.errors[key]);
    let u = [
        r.design["crank_counterweight_first_moment_x_kgm"],
        r.design["crank_counterweight_first_moment_y_kgm"],
    ];
    let rms = true_rms(NEAR_FOLD);
    let at_design = rms(u);
    assert!(
        (v - at_design).abs() <= err,
        "reported {v} ± {err}, true {at_design}"
    );
    // R² = c + gᵀu + uᵀHu exactly: six evaluations around the design give the exact
    // optimum (interior: |u| is far below m·r = 0.12 kg·m).
    let h = 1e-3;
    let r2 = |du: [f64; 2]| rms([u[0] + du[0], u[1] + du[1]]).powi(2);
    let (f0, fxp, fxm, fyp, fym, fxy) = (
        r2([0.0, 0.0]),
        r2([h, 0.0]),
        r2([-h, 0.0]),
        r2([0.0, h]),
        r2([0.0, -h]),
        r2([h, h]),
    );
    let (gx, gy) = ((fxp - fxm) / (2.0 * h), (fyp - fym) / (2.0 * h));
    let (hxx, hyy) = (
        (fxp - 2.0 * f0 + fxm) / (h * h),
        (fyp - 2.0 * f0 + fym) / (h * h),
    );
    let hxy = (fxy - fxp - fyp + f0) / (h * h);
    let det = hxx * hyy - hxy * hxy;
    let step = [(hyy * gx - hxy * gy) / det, (hxx * gy - hxy * gx) / det];
    let best = (f0 - 0.5 * (gx * step[0] + gy * step[1])).sqrt();
    assert!(
        (v - best).abs() <= err,
        "reported {v} ± {err}, exact optimum {best}"
    );
    assert!(best <= at_design + 1e-9 * at_design);
    // At 360 angles alone the figure was 108.4 N: the doubling is what moved it.
    assert!((v - 80.68).abs() < 0.01, "{v}");
    eprintln!("reported {v} ± {err:.2e}; true at the design {at_design}; exact optimum {best}");
}

/// Ten nanometres from the fold the count still converges (251.259 N, measured); 0.1 nm
/// from it (the spike ~10⁻⁴ rad wide) the grid meets its cap of 2¹⁰ doublings first: the
/// RMS objective is then `inaccurate`, and a warning says why, rather than `optimal`.
#[test]
fn an_rms_sharper_than_the_finest_grid_is_not_certified() {
    let sharp = with(NEAR_FOLD, "60.001 mm", "60.0000001 mm");
    let r = solve_scene(&parse_str(&sharp, Path::new("near-fold.toml")).unwrap());
    assert_eq!(r.status, Status::Inaccurate, "{:?}", r.warnings);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("RMS quadrature did not converge")),
        "{:?}",
        r.warnings
    );
}
