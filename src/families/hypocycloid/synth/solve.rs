//! [`solve`]: a hypocycloid scene's design (fixed or searched), its full evaluation —
//! coefficient tables, Lanchester pairs, objectives with their errors, the bounds the design
//! sits on — the zero search when asked, and the comparison with paper `004`.

use super::optimise::{evaluate, optimise, residual_rel, Eval};
use super::zero::zero_search;
use super::{
    field, CoefficientModel, CoefficientTable, Derived, Design, ForceCurves, HypocycloidScene,
    Objectives, OptStatus, OrderRow, Outcome, PaperCheck, Settings, ZeroPoint, ZeroRoot,
    ZeroSearchResult, ZeroStatus,
};
use crate::families::hypocycloid::model::{
    lanchester_pair, max_abs_y, Coefficients, Hypocycloid, ALPHA0_VARIANT2,
};
use crate::numeric::{periodic_peak_with, periodic_rms};
use crate::problem::FieldError;
use crate::report::numbers::key;
use crate::synth::ActiveBound;
use std::f64::consts::PI;

/// Solve a scene: optimise (λ, θ) if free, evaluate, balance, compare with the paper, and run
/// the zero search if asked. Invalid input is the only error; solver trouble is a status.
pub fn solve(scene: &HypocycloidScene, settings: &Settings) -> Result<Outcome, FieldError> {
    scene.validate()?;
    settings.validate()?;
    let s = settings;
    let mut warnings = Vec::new();
    let mut evals = 0usize;
    let fscale = scene.m_b * scene.r_carrier * scene.omega * scene.omega;
    let opt = optimise(scene, s, &mut evals, &mut warnings);
    let mut x = opt.x;
    // Keep the reported design feasible.
    let ym = max_abs_y(x[1], scene.alpha0).unwrap_or(f64::INFINITY);
    if x[0] * ym > 1.0 - scene.assembly_margin {
        x[0] = (1.0 - scene.assembly_margin) / ym;
    }
    let (l, t) = (x[0], x[1]);
    let e = match evaluate(scene, l, t, s) {
        Ok(e) => e,
        Err(err) => return Err(field("design.lambda", l, &err.to_string())),
    };
    evals += 1;
    let m = Hypocycloid {
        lambda: l,
        theta: t,
        alpha0: scene.alpha0,
    };
    let r = scene.r_carrier;
    let c = &e.coef;
    // A design that the search pushed onto a bound, and one that lost what makes the machine
    // hypocycloidal (the suction lengthening of paper 004), are said so.
    let (bounds, degenerate) = match opt.status {
        OptStatus::Analysis => (Vec::new(), None),
        status => (active_bounds(scene, l, t), degeneracy(status, &e, l, t, r)),
    };
    model_warnings(scene, &e, &mut warnings);
    let n_ord = scene.orders;
    let (sa, sb) = m.series_coefficients(scene.series_power, n_ord);
    let (objectives, errors) = objectives(scene, s, &m, &e)?;
    let mut derived = derived(scene, &e, &sa, evals as f64);
    let (zsr, zero_curve, zero_curve_series) = match &scene.zero_search {
        Some(_) => {
            let (z, zc, zcs) = zero_section(scene, s, &mut derived, &mut warnings);
            evals += z.evals;
            (Some(z), zc, zcs)
        }
        None => (None, Vec::new(), Vec::new()),
    };
    let paper = paper_checks(scene, &m, c, &sa, &sb, zsr.as_ref());
    let method = format!(
        "{}; coefficients: exact polynomial part + FFT of the O(λ³) remainder (n = {}); zero search: sign scan \
         + argmin Brent to {:e}; {evals} evaluations",
        opt.method, c.n_fft, s.root_tol
    );
    Ok(Outcome {
        design: Design {
            lambda: l,
            theta: t,
            carrier_radius_m: r,
            crank_arm_m: t * r,
            rod_length_m: r / l,
        },
        objectives,
        errors,
        derived,
        warnings,
        paper,
        method,
        status: opt.status,
        search: opt.search,
        degenerate,
        bounds,
        coefficients: coefficient_table(scene, c, fscale, sa, sb),
        balancing: scene
            .balance_orders
            .iter()
            .map(|&i| lanchester_pair(i, c.a[i], c.b[i], scene.m_b, r, scene.omega))
            .collect(),
        zero_curve,
        zero_curve_series,
        zero_search: zsr,
        force_curves: force_curves(scene, &m, c, s.plot_samples, fscale),
    })
}

/// The objectives of the evaluated design `e` of `m` and their errors: the residual force's
/// peak (from the evaluation) and RMS, the unbalanced peak, the stroke and the suction gain.
fn objectives(
    scene: &HypocycloidScene,
    s: &Settings,
    m: &Hypocycloid,
    e: &Eval,
) -> Result<(Objectives, Objectives), FieldError> {
    let (c, l, r) = (&e.coef, m.lambda, scene.r_carrier);
    let fscale = scene.m_b * scene.r_carrier * scene.omega * scene.omega;
    // Unbalanced peak and residual RMS.
    let unb = periodic_peak_with(|p| m.piston(p).dds.abs(), s.peak_samples, s.peak_tol())
        .map_err(|err| field("design.lambda", l, &err.to_string()))?;
    let rms = periodic_rms(
        |p| residual_rel(m, c, &scene.balance_orders, p),
        2 * s.peak_samples,
    );
    let cerr: f64 = scene
        .balance_orders
        .iter()
        .map(|&i| (i * i) as f64 * c.err[i])
        .sum();
    let objectives = Objectives {
        c4: c.a[4],
        residual_force_peak_n: fscale * e.residual_peak,
        residual_force_rms_n: fscale * rms.rms,
        unbalanced_force_peak_n: fscale * unb.peak.fx,
        stroke_m: r * e.stroke,
        suction_gain: e.suction_gain,
    };
    let errors = Objectives {
        c4: c.err[4],
        residual_force_peak_n: fscale * e.residual_peak_err,
        residual_force_rms_n: fscale * (rms.error + cerr),
        unbalanced_force_peak_n: fscale * unb.error,
        stroke_m: r * e.stroke_err.max(f64::EPSILON * e.stroke),
        suction_gain: 1e-9 / PI,
    };
    Ok((objectives, errors))
}

/// The bound each searched variable sits on, and who set it: a machine limit
/// (θ ≥ r_min/R, λ ≥ R/L_max) or the design range.
fn active_bounds(scene: &HypocycloidScene, l: f64, t: f64) -> Vec<ActiveBound> {
    let r = scene.r_carrier;
    let (lb, tb) = (scene.lambda.bounds(), scene.theta.bounds());
    let set_by = |name: &str, lo: f64| -> (String, String) {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
        match name {
            "lambda" => match scene.max_rod_length.filter(|&lm| close(lo, r / lm)) {
                Some(lm) => ("objective.max_rod_length".into(), format!(
                    "the residual force falls as the rod L = R/λ grows: the rod limit ({:.4} mm) sets L = {:.4} mm",
                    lm * 1e3, r / l * 1e3
                )),
                None => ("design.lambda".into(), format!(
                    "the residual force falls as λ → 0, i.e. as the rod L = R/λ = {:.4} m grows: the range, not an interior optimum, sets the rod (give objective.max_rod_length)",
                    r / l
                )),
            },
            _ => match scene.min_crank_arm.filter(|&am| close(lo, am / r)) {
                Some(am) => ("objective.min_crank_arm".into(), format!(
                    "the crank arm r = θR would shrink further: the arm limit ({:.4} mm) sets r",
                    am * 1e3
                )),
                None => ("design.theta".into(), format!(
                    "the range, not an interior optimum, sets the crank arm r = θR = {:.4} mm (give objective.min_crank_arm)",
                    t * r * 1e3
                )),
            },
        }
    };
    let mut bounds = Vec::new();
    for (name, v, b) in [("lambda", l, lb), ("theta", t, tb)] {
        let lower = set_by(name, b.0);
        let upper = (
            format!("design.{name}"),
            "the range's upper end, not an interior optimum, decides the design".to_string(),
        );
        if b.1 > b.0 {
            bounds.extend(ActiveBound::check(
                &format!("design.{name}"),
                v,
                b,
                1e-6,
                (&lower.0, &lower.1),
                (&upper.0, &upper.1),
            ));
        }
    }
    bounds
}

/// Why a searched design is degenerate: without suction lengthening it is a plain
/// slider-crank, not the hypocycloidal machine of paper 004.
fn degeneracy(status: OptStatus, e: &Eval, l: f64, t: f64, r: f64) -> Option<String> {
    (status != OptStatus::Infeasible && e.suction_gain <= 1e-9).then(|| {
        format!(
            "the best design found has no suction lengthening (suction gain {:.1e}) with a crank arm \
             r = θR = {:.4} mm ({:.2} % of R) and a rod L = {:.4} m: it is a plain slider-crank, not the \
             hypocycloidal machine of paper 004; set hypocycloid.min_suction_gain (as variant 2 does) or a \
             lower bound on θ to ask for one",
            e.suction_gain,
            t * r * 1e3,
            100.0 * t,
            r / l
        )
    })
}

/// Warnings on the coefficient model: the paper's truncated series in use, an FFT that did
/// not converge.
fn model_warnings(scene: &HypocycloidScene, e: &Eval, warnings: &mut Vec<String>) {
    let c = &e.coef;
    if scene.coefficients == CoefficientModel::Series {
        warnings.push(format!(
            "model.coefficients = \"series\": the balancing and the objectives use the paper's series truncated at \
             z^{} (y^{}), not the exact coefficients; the coefficient errors reported are the FFT's, not the \
             truncation's",
            scene.series_power,
            2 * scene.series_power
        ));
    }
    if !c.converged {
        warnings.push(format!(
            "the Fourier coefficients did not converge to the rounding floor at n_fft = {} (λ·max|y| = {:.6}); the \
             errors reported are the last change",
            c.n_fft, e.ratio_ymax
        ));
    }
}

/// The derived figures of a design (those of the zero search left empty).
fn derived(scene: &HypocycloidScene, e: &Eval, sa: &[f64], evaluations: f64) -> Derived {
    let c = &e.coef;
    let fscale = scene.m_b * scene.r_carrier * scene.omega * scene.omega;
    let max_abs_b1_b6 = c.b[1..=6.min(scene.orders)]
        .iter()
        .fold(0.0f64, |m, b| m.max(b.abs()));
    Derived {
        b4: c.b[4],
        c4_series: sa[4],
        c4_series_minus_exact: sa[4] - c.a[4],
        lambda_ymax: e.ratio_ymax,
        assembly_margin: 1.0 - e.ratio_ymax,
        n_fft: c.n_fft as f64,
        force_scale_n: fscale,
        force_order4_amplitude_n: fscale * 16.0 * c.amplitude(4),
        suction_angle_rad: (e.suction_gain + 1.0) * PI,
        evaluations,
        zero_curve_series_max_dtheta: None,
        zero_curve_series_worst_lambda: None,
        zero_roots: None,
        zero_max_abs_at_root: None,
        omega_rad_s: scene.omega,
        max_abs_b1_b6,
        force_ratio_order3_to_order1: 9.0 * c.a[3].hypot(c.b[3]) / c.a[1].hypot(c.b[1]),
    }
}

/// The coefficient tables: exact and series coefficients to the scene's order, one row per
/// order with its force amplitude.
fn coefficient_table(
    scene: &HypocycloidScene,
    c: &Coefficients,
    fscale: f64,
    sa: Vec<f64>,
    sb: Vec<f64>,
) -> CoefficientTable {
    let n_ord = scene.orders;
    let rows: Vec<OrderRow> = (1..=n_ord)
        .map(|i| OrderRow {
            order: i,
            a: c.a[i],
            b: c.b[i],
            error: c.err[i],
            a_series: sa[i],
            b_series: sb[i],
            force_amplitude: fscale * (i * i) as f64 * c.amplitude(i),
            balanced: scene.balance_orders.contains(&i),
        })
        .collect();
    CoefficientTable {
        a: c.a[..=n_ord].to_vec(),
        b: c.b[..=n_ord].to_vec(),
        error: c.err[..=n_ord].to_vec(),
        a_series: sa,
        b_series: sb,
        series_power: scene.series_power,
        n_fft: c.n_fft,
        converged: c.converged,
        rows,
    }
}

/// The zero search of the scene (which has one), its zero curves (exact, and the series'
/// nearest roots), its derived figures and warnings.
fn zero_section(
    scene: &HypocycloidScene,
    s: &Settings,
    derived: &mut Derived,
    warnings: &mut Vec<String>,
) -> (ZeroSearchResult, Vec<ZeroPoint>, Vec<ZeroPoint>) {
    let zs = scene.zero_search.as_ref().expect("a zero search");
    let z = zero_search(
        scene.alpha0,
        zs,
        scene.series_power,
        scene.assembly_margin,
        s,
    );
    let zc = z
        .roots
        .iter()
        .map(|r| ZeroPoint {
            lambda: r.lambda,
            theta: r.theta,
        })
        .collect();
    let zcs = z
        .roots
        .iter()
        .filter_map(|r| {
            r.series_theta.map(|t| ZeroPoint {
                lambda: r.lambda,
                theta: t,
            })
        })
        .collect();
    if !z.single_valued {
        warnings.push("the zero set has several branches in some λ columns".into());
    }
    if let Some(zb) = z
        .roots
        .iter()
        .map(|r| (r.series_theta.map(|t| (t - r.theta).abs()), r))
        .fold(None, |acc: Option<(f64, ZeroRoot)>, (d, r)| match d {
            Some(d) if acc.is_none_or(|a| d > a.0) => Some((d, *r)),
            _ => acc,
        })
    {
        derived.zero_curve_series_max_dtheta = Some(zb.0);
        derived.zero_curve_series_worst_lambda = Some(zb.1.lambda);
    }
    let missing = z.roots.iter().filter(|r| r.series_theta.is_none()).count();
    if missing > 0 {
        warnings.push(format!(
            "the truncated series (power {}) has no zero in {missing} of the {} λ columns where the exact \
             coefficient has one",
            scene.series_power,
            z.roots.len()
        ));
    }
    derived.zero_roots = Some(z.roots.len() as f64);
    derived.zero_max_abs_at_root = Some(z.max_abs_at_root);
    (z, zc, zcs)
}

/// The forces over one turn for the plots, at `np` angles.
fn force_curves(
    scene: &HypocycloidScene,
    m: &Hypocycloid,
    c: &Coefficients,
    np: usize,
    fscale: f64,
) -> ForceCurves {
    let r = scene.r_carrier;
    let phi: Vec<f64> = (0..np)
        .map(|j| 2.0 * PI * j as f64 / (np - 1) as f64)
        .collect();
    ForceCurves {
        unbalanced: phi.iter().map(|&p| -fscale * m.piston(p).dds).collect(),
        residual: phi
            .iter()
            .map(|&p| fscale * residual_rel(m, c, &scene.balance_orders, p))
            .collect(),
        position: phi.iter().map(|&p| r * m.piston(p).s_rel).collect(),
        phi,
    }
}

/// What the paper states (it prints no numbers, only structure and claims) against the
/// computation.
#[allow(clippy::needless_range_loop)] // indexes a, b, series a, series b together
fn paper_checks(
    scene: &HypocycloidScene,
    m: &Hypocycloid,
    c: &Coefficients,
    sa: &[f64],
    sb: &[f64],
    z: Option<&ZeroSearchResult>,
) -> Vec<PaperCheck> {
    let mut v = Vec::new();
    let p = scene.series_power;
    let v2 = (scene.alpha0 - ALPHA0_VARIANT2).rem_euclid(2.0 * PI) < 1e-12;
    let v1 = scene.alpha0.rem_euclid(2.0 * PI) < 1e-12;
    for i in 1..=6 {
        v.push(PaperCheck::new(
            format!("a{i} (C{i}{})", if v2 { "^I" } else { "" }),
            format!("coefficients.a.{i}"),
            sa[i],
            c.a[i],
            format!(
                "paper's method = binomial series to z^{p} (y^{}); difference {:.3e} (series truncation error; the \
                 exact value's error is {:.1e})",
                2 * p,
                sa[i] - c.a[i],
                c.err[i]
            ),
        ));
    }
    if v2 {
        v.push(PaperCheck::new(
            "C1^I (from m'_I r'_I = ½ m_B R)",
            "coefficients.a.1",
            1.0,
            c.a[1],
            "the root contributes no cos φ term in variant 2 (its cosine part has only even orders)",
        ));
        v.push(PaperCheck::new(
            "C2^II (sine part of order 2)",
            "coefficients.b.2",
            sb[2],
            c.b[2],
            "−θ exactly: only the crank term −θ sin 2φ contributes; the root's sine part has odd orders only",
        ));
        v.push(PaperCheck::new(
            "a3 (paper: the cosine part S^I has no 3rd order)",
            "coefficients.a.3",
            0.0,
            c.a[3],
            "zero by the symmetry y(π − φ) = y(φ)",
        ));
    }
    if v1 {
        v.push(PaperCheck::new(
            "b1..b6 (paper: only cosines in variant 1)",
            key!("derived", Derived, max_abs_b1_b6),
            0.0,
            c.b[1..=6].iter().fold(0.0f64, |a, &b| a.max(b.abs())),
            "S is even in φ because y is odd: max |b_i| shown",
        ));
    }
    // The paper calls the 3rd-order force negligible ("C3, C1^II, C3^II ~ λθ").
    let f1 = c.amplitude(1);
    let f3 = 9.0 * c.amplitude(3);
    v.push(PaperCheck::new(
        "|Φ3|/|Φ1| (paper: 3rd order negligible, ∝ λθ)",
        key!("derived", Derived, force_ratio_order3_to_order1),
        0.0,
        f3 / f1,
        format!(
            "the coefficient is O(λθ) = {:.3} but the force carries i² = 9: at λ = {}, θ = {} the 3rd-order force is \
             {:.0}% of the 1st",
            m.lambda * m.theta,
            m.lambda,
            m.theta,
            100.0 * f3 / f1
        ),
    ));
    if let Some(z) = z {
        let computed = match z.status {
            ZeroStatus::Found => z.max_abs_at_root,
            _ => z.grid_min_abs.map(|g| g.value.abs()).unwrap_or(f64::NAN),
        };
        v.push(PaperCheck::new(
            format!(
                "a{} = 0 for some (λ, θ) (paper's conjecture, variant 2)",
                z.order
            ),
            match z.status {
                ZeroStatus::Found => "zero_search.max_abs_at_root",
                _ => "zero_search.min_abs",
            },
            0.0,
            if computed.is_finite() { computed } else { -1.0 },
            match z.status {
                ZeroStatus::Found => format!(
                    "{} roots found; computed = max |a| at a root. {}",
                    z.roots.len(),
                    z.reason
                ),
                ZeroStatus::NoZero => {
                    format!("no zero; computed = min |a| on the grid. {}", z.reason)
                }
                ZeroStatus::Infeasible => z.reason.clone(),
            },
        ));
    }
    v
}
