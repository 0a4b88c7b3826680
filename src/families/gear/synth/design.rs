//! The analysis of one gear design (closure, poles and zeros of µ, peak |µ|, gear 2's
//! curvature) and the design of the eccentricity: a sweep over its bounds, then Brent — the
//! root of the worst constraint margin at a constraint boundary (argmin's `BrentRoot`
//! through [`crate::numeric::brent_root`]) or the maximum of the ratio variation between
//! samples (Brent's fmin, hand-written in [`crate::numeric::brent_max`]).

use super::outcome::report;
use super::{Analysis, GearScene, Outcome, Settings, SolveError, Status, SweepRow, Var};
use crate::families::gear::model::{
    closing_center_distance, min_gear2_curvature, peak_mu_with, singularities_with,
    EccentricCircle, GearPair,
};
use crate::numeric::{brent_max, brent_root};
use crate::synth::SearchEvidence;

/// Build and analyse the pair of `scene` at eccentricity `e`: closing centre distance,
/// all poles and zeros, peak |µ| on the working window, gear 2's minimum curvature.
pub fn analyse(scene: &GearScene, e: f64, settings: &Settings) -> Result<Analysis, SolveError> {
    let c = EccentricCircle::new(scene.pitch_radius, e)?;
    let closure = closing_center_distance(&c, scene.turns_gear1, scene.turns_gear2)?;
    let pair = GearPair::new(c, scene.generating_radius, closure.a, scene.omega1)?;
    let sing = singularities_with(
        &pair,
        settings.samples_per_arch,
        settings.refine_poles.then_some(settings.pole_tol),
    )?;
    let peak = peak_mu_with(
        &pair,
        &sing,
        scene.pole_window,
        settings.peak_samples_per_arch,
        settings.refine_peaks.then_some(settings.peak_xtol),
    )?;
    let curvature = min_gear2_curvature(&pair, settings.curvature_samples)?;
    let evals = sing.evals + peak.evals + settings.curvature_samples;
    Ok(Analysis {
        pair,
        closure,
        sing,
        peak,
        curvature,
        evals,
    })
}

/// Constraint margins (≤ 0 feasible), dimensionless.
fn margins(scene: &GearScene, an: &Analysis) -> Vec<(&'static str, f64)> {
    let mut m = Vec::new();
    if let Some(lim) = scene.max_sliding_coefficient {
        m.push((
            "objective.max_sliding_coefficient",
            an.peak.value / lim - 1.0,
        ));
    }
    if scene.require_gear2_convex {
        m.push((
            "objective.require_gear2_convex",
            -an.curvature.0 * scene.pitch_radius,
        ));
    }
    if let Some(lim) = scene.max_pressure_angle {
        m.push((
            "objective.max_pressure_angle",
            an.max_pitch_pressure_angle() / lim - 1.0,
        ));
    }
    m
}

fn worst_margin(scene: &GearScene, e: f64, settings: &Settings) -> f64 {
    match analyse(scene, e, settings) {
        Ok(an) => margins(scene, &an)
            .iter()
            .map(|x| x.1)
            .fold(f64::NEG_INFINITY, f64::max)
            .max(-1e300),
        Err(_) => 1.0,
    }
}

/// One sample of the sweep: e, and (ratio variation, worst margin) where the pair exists.
type Sample = (f64, Option<(f64, f64)>);

/// The sweep of `sweep_points` equally spaced e over [min, max]: each sample's objective and
/// worst margin, and its row for the result.
fn sweep(
    scene: &GearScene,
    settings: &Settings,
    min: f64,
    max: f64,
) -> (Vec<Sample>, Vec<SweepRow>) {
    let n = settings.sweep_points;
    let mut sweep = Vec::new();
    let mut rows: Vec<Sample> = Vec::new();
    for k in 0..n {
        let e = min + (max - min) * k as f64 / (n - 1) as f64;
        match analyse(scene, e, settings) {
            Ok(an) => {
                let ms = margins(scene, &an);
                let worst = ms.iter().map(|x| x.1).fold(f64::NEG_INFINITY, f64::max);
                let feasible = worst <= 0.0;
                sweep.push(SweepRow {
                    eccentricity_m: e,
                    center_distance_m: an.pair.a,
                    ratio_min: an.pair.ratio_range().0,
                    ratio_max: an.pair.ratio_range().1,
                    ratio_variation: an.ratio_variation(),
                    peak_sliding_coefficient: an.peak.value,
                    min_gear2_curvature_per_m: an.curvature.0,
                    max_pitch_pressure_angle_rad: an.max_pitch_pressure_angle(),
                    feasible,
                });
                rows.push((e, Some((an.ratio_variation(), worst))));
            }
            Err(_) => rows.push((e, None)),
        }
    }
    (rows, sweep)
}

/// The sweep's evidence: the best objective of each maximal run of feasible samples (a run
/// is a basin of the 1-D search), best first.
fn sweep_evidence(rows: &[Sample], min: f64, max: f64) -> SearchEvidence {
    let n = rows.len();
    let mut run_best: Vec<f64> = Vec::new();
    let mut in_run = false;
    for r in rows {
        match r.1.filter(|x| x.1 <= 0.0) {
            Some((o, _)) if in_run => {
                let last = run_best.last_mut().expect("in a run");
                *last = last.max(o);
            }
            Some((o, _)) => {
                run_best.push(o);
                in_run = true;
            }
            None => in_run = false,
        }
    }
    run_best.sort_by(|a, b| b.total_cmp(a));
    SearchEvidence {
        method: format!(
            "sweep of {n} equally spaced eccentricities over [{min:e}, {max:e}] m, then Brent \
             (Brent 1973) on the best sample's neighbourhood; no bound on the constraints \
             between samples, so a feasible e between two infeasible samples can be missed"
        ),
        starts: 1,
        distinct_basins: run_best.len(),
        evaluations: n,
        best_values: run_best.iter().take(5).copied().collect(),
        starts_at_best: 1,
        spread_rel: (run_best.len() > 1).then(|| (run_best[0] - run_best[1]) / run_best[0].abs()),
    }
}

/// The designed e from the sweep: the best feasible sample refined by Brent — to the
/// constraint boundary when a better neighbour is infeasible, to the interior maximum
/// otherwise — or the least violating sample when none is feasible. The e, the status and
/// the design's error bound; the method into `method`, the analyses into `search`.
fn refine(
    scene: &GearScene,
    settings: &Settings,
    rows: &[Sample],
    search: &mut SearchEvidence,
    method: &mut String,
) -> Result<(f64, Status, f64), SolveError> {
    let n = rows.len();
    let best = rows
        .iter()
        .enumerate()
        .filter_map(|(k, r)| r.1.filter(|x| x.1 <= 0.0).map(|x| (k, x.0)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let tol = settings.design_rtol * scene.pitch_radius;
    let Some((k, obj)) = best else {
        let k = rows
            .iter()
            .enumerate()
            .filter_map(|(k, r)| r.1.map(|x| (k, x.1)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|x| x.0)
            .unwrap_or(0);
        method.push_str(&format!(
            "sweep of {n} eccentricities: none feasible; reporting the least violating. "
        ));
        return Ok((rows[k].0, Status::Infeasible, 0.0));
    };
    // A neighbour with a larger objective but infeasible: the optimum is on the constraint
    // boundary between them.
    let nb = [k.checked_sub(1), (k + 1 < n).then_some(k + 1)];
    let mut cand = None;
    for j in nb.into_iter().flatten() {
        if let Some((o, w)) = rows[j].1 {
            if w > 0.0 && o > obj {
                cand = Some(j);
            }
        } else {
            cand = Some(j);
        }
    }
    if let Some(j) = cand {
        let count = std::cell::Cell::new(0usize);
        let f = |x: f64| {
            count.set(count.get() + 1);
            worst_margin(scene, x, settings)
        };
        let root = brent_root(f, rows[k].0, rows[j].0, tol)?;
        // Keep the feasible side of the boundary.
        let mut x = root.x;
        let step = if rows[j].0 > rows[k].0 { -tol } else { tol };
        let mut guard = 0;
        while f(x) > 0.0 && guard < 8 {
            x += step;
            guard += 1;
        }
        search.evaluations += count.get();
        method.push_str(&format!(
            "sweep of {n} eccentricities, then Brent root of the worst constraint margin (argmin BrentRoot) on [{:.6e}, {:.6e}] m ({} analyses, tol {:.1e} m). ",
            rows[k].0.min(rows[j].0),
            rows[k].0.max(rows[j].0),
            count.get(),
            tol
        ));
        Ok((x, Status::ConstraintBound, 2.0 * tol))
    } else if k == 0 || k + 1 == n {
        method.push_str(&format!("sweep of {n} eccentricities: best at the bound. "));
        Ok((rows[k].0, Status::AtBound, 0.0))
    } else {
        let count = std::cell::Cell::new(0usize);
        let g = |x: f64| {
            count.set(count.get() + 1);
            analyse(scene, x, settings)
                .map(|a| a.ratio_variation())
                .unwrap_or(f64::NEG_INFINITY)
        };
        let ext = brent_max(g, rows[k - 1].0, rows[k + 1].0, tol)?;
        search.evaluations += count.get();
        method.push_str(&format!(
            "sweep of {n} eccentricities, then Brent maximisation (Brent's fmin, hand-written numeric::brent_max) ({} analyses). ",
            count.get()
        ));
        Ok((ext.x, Status::Optimal, tol))
    }
}

/// Solve the scene: analyse the given e, or design e when it is free.
///
/// Returns `Err` only for impossible input (a field error such as e ≥ R, or settings out
/// of range); an infeasible design is an `Ok` with [`Status::Infeasible`].
pub fn solve(scene: &GearScene, settings: &Settings) -> Result<Outcome, SolveError> {
    scene.validate()?;
    settings.validate()?;
    let mut method = String::new();
    let mut sweep_rows = Vec::new();
    let mut design_error = 0.0;
    let mut search: Option<SearchEvidence> = None;
    let (e, status) = match scene.eccentricity {
        Var::Fixed(e) => (e, Status::Analysed),
        Var::Free { min, max } => {
            let (rows, rows_out) = sweep(scene, settings, min, max);
            sweep_rows = rows_out;
            let mut ev = sweep_evidence(&rows, min, max);
            let (e, status, error) = refine(scene, settings, &rows, &mut ev, &mut method)?;
            design_error = error;
            search = Some(ev);
            (e, status)
        }
    };
    let an = analyse(scene, e, settings)?;
    let mut out = report(scene, &an, settings)?;
    out.status = status;
    out.sweep = sweep_rows;
    if let Some(ev) = search.as_mut() {
        // The refined design heads the list (it is at least the best sample).
        let v = out.objectives.ratio_variation;
        if status != Status::Infeasible && ev.best_values.first().is_none_or(|&b| v >= b) {
            ev.best_values.insert(0, v);
            ev.best_values.truncate(5);
        }
    }
    out.search = search;
    out.method = format!(
        "{method}Analysis: closure a by Brent (argmin BrentRoot) on the trapezoid closure integral ({} integrals); poles: {} samples/arch + Brent (argmin BrentRoot) to {:.0e} rad; peak |µ|: {} samples/arch + Brent's fmin (hand-written, numeric::brent_max) to {:.0e} rad; {} contact evaluations.",
        an.closure.evals, settings.samples_per_arch, settings.pole_tol, settings.peak_samples_per_arch, settings.peak_xtol, an.evals
    );
    if design_error > 0.0 {
        out.derived.eccentricity_error_m = Some(design_error);
    }
    out.derived.sweep_best_feasible_eccentricity_m = out
        .sweep
        .iter()
        .filter(|s| s.feasible)
        .max_by(|a, b| a.ratio_variation.total_cmp(&b.ratio_variation))
        .map(|best| best.eccentricity_m);
    if !out.sweep.is_empty() {
        out.derived.sweep_feasible_points =
            Some(out.sweep.iter().filter(|s| s.feasible).count() as f64);
    }
    Ok(out)
}
