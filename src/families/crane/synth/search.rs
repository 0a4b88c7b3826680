//! The crane's design search: Δh over the unit box of the free variables as a problem of the
//! shared search layer — its penalised cost for the Halton global stage, its head-height
//! extrema and constraints as the pieces of the trust-region SQP
//! ([`crate::synth::search::sqp`]) — and [`solve`], which runs the multistart and evaluates
//! the best design in full.

use super::evaluate::{build, evaluate};
use super::outcome::report;
use super::{is_free, Basin, CraneScene, Outcome, Settings, Status, TiePinLimit, Vars, SAME_BASIN};
use crate::families::crane::model::{level_extrema, Boom, Branch, Guide, Synthesis};
use crate::problem::FieldError;
use crate::synth::search::starts::{distance, distinct_starts, halton_points, ranked};
use crate::synth::search::{sqp, Minimax, Probe, SameBasin, SearchEvidence, Sqp};

/// Cost of an infeasible geometry (in units of the length scale; a valid Δh is ~1e-2).
const NO_GEOMETRY_COST: f64 = 10.0;

/// The design problem over the unit box of the free variables: the penalised cost of the
/// global stage and the pieces of the local SQP.
struct Objective<'a> {
    scene: &'a CraneScene,
    settings: &'a Settings,
    free: Vec<usize>,
    base: [f64; 6],
    lo: [f64; 6],
    hi: [f64; 6],
}

/// Signed constraints of a built design over the length scale (≤ 0 met): each tie-pin limit
/// (|AB| − R, lo − x_B, x_B − hi, lo − y_B, y_B − hi), the reach shortfall at maximum reach,
/// the reach excess at minimum reach and the head-height shortfall. `None` for the
/// straight-guide limit under a bounded tie-pin limit (B at infinity).
fn signed_constraints(scene: &CraneScene, boom: &Boom, syn: &Synthesis) -> Option<Vec<f64>> {
    let l = scene.length_scale();
    let mut c = Vec::with_capacity(8);
    let t = &scene.tie_pin;
    if t != &TiePinLimit::default() {
        let Guide::Circle { centre: b, .. } = syn.guide else {
            return None;
        };
        if let Some(r) = t.max_distance {
            c.push((b.norm() - r) / l);
        }
        if let Some([lo, hi]) = t.x_range {
            c.extend([(lo - b.x) / l, (b.x - hi) / l]);
        }
        if let Some([lo, hi]) = t.y_range {
            c.extend([(lo - b.y) / l, (b.y - hi) / l]);
        }
    }
    let (a, k) = (&boom.angles, boom.k);
    c.push((scene.reach_max - scene.foot_offset - boom.l_c * a.unit_reach_max(k)) / l);
    c.push((boom.l_c * a.unit_reach_min(k) - (scene.reach_min - scene.foot_offset)) / l);
    c.push((scene.lift_height - scene.foot_height - boom.head_height()) / l);
    Some(c)
}

impl<'a> Objective<'a> {
    /// The problem of a scene: the free variables, their bounds, the fixed ones at the
    /// middle of their (point) bounds.
    fn new(scene: &'a CraneScene, settings: &'a Settings) -> Objective<'a> {
        let vars = scene.vars();
        let mut base = [0.0; 6];
        let (mut lo, mut hi) = ([0.0; 6], [0.0; 6]);
        for i in 0..6 {
            (lo[i], hi[i]) = vars[i].bounds();
            base[i] = 0.5 * (lo[i] + hi[i]);
        }
        Objective {
            scene,
            settings,
            free: (0..6).filter(|&i| is_free(&vars[i])).collect(),
            base,
            lo,
            hi,
        }
    }

    /// Design point of unit coordinates u (clamped to the box) and the distance outside it.
    fn point(&self, u: &[f64]) -> ([f64; 6], f64) {
        let mut x = self.base;
        let mut outside = 0.0;
        for (&i, &ui) in self.free.iter().zip(u) {
            let c = ui.clamp(0.0, 1.0);
            outside += (ui - c).abs();
            x[i] = self.lo[i] + c * (self.hi[i] - self.lo[i]);
        }
        (x, outside)
    }

    /// Δh/L + penalty·(violations/L + distance outside the box); a geometry that fails costs
    /// [`NO_GEOMETRY_COST`] more. The screening cost of the global stage.
    fn value(&self, u: &[f64]) -> f64 {
        let (x, outside) = self.point(u);
        let l = self.scene.length_scale();
        let w = self.settings.penalty;
        match evaluate(self.scene, &x, self.settings) {
            Ok(ev) => match ev.delta_h() {
                Some(dh) if ev.tie_pin_violation.is_finite() => {
                    dh / l + w * (ev.violation() / l + outside)
                }
                _ => NO_GEOMETRY_COST + w * outside,
            },
            Err(_) => NO_GEOMETRY_COST + w * outside,
        }
    }

    /// The built design at u if it is a valid linkage on one branch.
    fn linkage(&self, u: &[f64]) -> Option<(Boom, Synthesis)> {
        let (x, _) = self.point(u);
        let (boom, syn) = build(self.scene, &x).ok()?;
        matches!(syn.branch, Branch::Consistent(_)).then_some((boom, syn))
    }
}

/// Δh as a minimax: the pieces are the local extrema of the levelled height (the head's, or
/// the load's with `minimize = "load-delta-h"`) over the
/// normalised boom angle t = (φ − φ_min)/(φ_max − φ_min), heights and constraints over the
/// length scale L.
impl Minimax for Objective<'_> {
    fn probe(&self, u: &[f64]) -> Option<Probe> {
        let (boom, syn) = self.linkage(u)?;
        let cons = signed_constraints(self.scene, &boom, &syn)?;
        let link = &syn.linkage;
        let [p0, p1] = link.phi_range;
        let ext = level_extrema(
            link,
            &self.scene.level,
            self.settings.path_samples,
            self.settings.xtol,
        )
        .ok()?;
        let l = self.scene.length_scale();
        let pieces = |m: bool| -> Vec<(f64, f64)> {
            ext.iter()
                .filter(|e| e.is_max == m)
                .map(|e| ((e.phi - p0) / (p1 - p0), e.y / l))
                .collect()
        };
        Some(Probe::new(pieces(true), pieces(false), cons))
    }

    fn values(&self, u: &[f64], ts: &[f64]) -> Option<Vec<f64>> {
        let (boom, syn) = self.linkage(u)?;
        let mut v = signed_constraints(self.scene, &boom, &syn)?;
        let link = &syn.linkage;
        let [p0, p1] = link.phi_range;
        let l = self.scene.length_scale();
        for &t in ts {
            v.push(self.scene.level.height(link.pose(p0 + t * (p1 - p0))?.c) / l);
        }
        Some(v)
    }

    fn constraints(&self, u: &[f64]) -> Option<Vec<f64>> {
        let (boom, syn) = self.linkage(u)?;
        signed_constraints(self.scene, &boom, &syn)
    }
}

/// What the multistart found.
struct Found {
    /// The best design.
    x: [f64; 6],
    /// The method, in words.
    method: String,
    /// Each local search.
    basins: Vec<Basin>,
    /// Whether the best local search converged.
    converged: bool,
    /// Evaluations of Δh spent.
    evaluations: usize,
}

/// The multistart: Halton points (index from 1) over the unit box ranked by the penalised
/// cost, then the SQP from the best points at least 0.15·√n apart.
fn multistart(obj: &Objective) -> Found {
    let settings = obj.settings;
    let n = obj.free.len();
    let pts: Vec<(Vec<f64>, f64)> = halton_points(settings.global_samples * n, n)
        .into_iter()
        .map(|u| {
            let c = obj.value(&u);
            (u, c)
        })
        .collect();
    let mut evaluations = pts.len();
    let min_sep = 0.15 * (n as f64).sqrt();
    let starts = distinct_starts(
        &ranked(pts),
        settings.local_starts,
        |_| true,
        |s, u| distance(s, u) >= min_sep,
    );
    let name = |u: &[f64]| {
        let (x, _) = obj.point(u);
        Vars::of(&x).named(&obj.free)
    };
    let tol = settings.constraint_tol;
    let l = obj.scene.length_scale();
    let local = Sqp {
        max_iters: settings.local_max_iters,
        tol: settings.local_tol,
        penalty: settings.penalty,
    };
    let mut basins = Vec::new();
    let mut best: Option<(Vec<f64>, f64, bool, bool)> = None;
    for s in starts {
        let run = sqp(obj, &s, &local);
        evaluations += run.evaluations;
        let (dh, feasible, merit) = match &run.probe {
            Some(p) => (
                Some(p.value * l),
                p.cons.iter().all(|&c| c <= tol),
                p.merit(settings.penalty),
            ),
            None => (None, false, NO_GEOMETRY_COST),
        };
        basins.push(Basin {
            start: name(&s),
            end: name(&run.u),
            delta_h_m: dh,
            cost: merit,
            converged: run.converged,
            feasible,
            iterations: run.iterations,
        });
        // Feasible ends first, then the smaller merit.
        let better = best
            .as_ref()
            .is_none_or(|b| (feasible && !b.3) || (feasible == b.3 && merit < b.1));
        if better {
            best = Some((run.u, merit, run.converged, feasible));
        }
    }
    let (u, _, converged, _) = best.expect("at least one start");
    let (x, _) = obj.point(&u);
    let method = format!(
        "multistart: {} Halton points (global stage, penalised cost), then trust-region SQP (Fletcher's Sl1QP: \
         minimax of the {}-height extrema, constraints linearised with elastic slacks, damped BFGS, each QP by a dense active-set method (clarabel where its check fails), \
         second-order correction onto the active constraints) \
         from the {} best distinct points (at most {} iterations each, stop at a predicted gain below {:e} of the \
         merit); l1 penalty {} in the merit",
        settings.global_samples * n,
        match obj.scene.level {
            crate::families::crane::model::Level::Head => "head",
            crate::families::crane::model::Level::Load(_) => "load",
        },
        basins.len(),
        settings.local_max_iters,
        settings.local_tol,
        settings.penalty
    );
    Found {
        x,
        method,
        basins,
        converged,
        evaluations,
    }
}

/// Solve a crane scene: evaluate it when every variable is fixed, otherwise minimise Δh over
/// the free variables (Halton global stage + trust-region SQP from the best distinct points),
/// then evaluate the best design in full (path, checks, thesis comparison).
///
/// `Err` only for a scene or settings field that is not allowed (including an optimisation
/// without a tie-pin limit, which is degenerate); every mechanism failure is a [`Status`].
pub fn solve(scene: &CraneScene, settings: &Settings) -> Result<Outcome, FieldError> {
    scene.validate()?;
    settings.validate()?;
    let obj = Objective::new(scene, settings);
    let mut warnings = Vec::new();
    let Some(found) = (!obj.free.is_empty()).then(|| multistart(&obj)) else {
        let mut out = report(scene, settings, &obj.base, &mut warnings);
        out.method = format!(
            "evaluation of the given design (all variables fixed); {} evaluations of delta h",
            out.evaluations
        );
        out.warnings = warnings;
        return Ok(out);
    };
    let mut out = report(scene, settings, &found.x, &mut warnings);
    out.evaluations += found.evaluations;
    out.method = format!(
        "{}; {} evaluations of delta h",
        found.method, out.evaluations
    );
    out.basins = found.basins;
    if out.status == Status::Evaluated {
        out.status = Status::BestFound;
    }
    if !found.converged {
        warnings.push("the best local search stopped at its iteration limit".into());
    }
    let search = SearchEvidence::of_ends(
        "Halton global stage + trust-region SQP (Fletcher's Sl1QP) from the best distinct points"
            .into(),
        out.basins
            .iter()
            .filter(|b| b.feasible)
            .filter_map(|b| b.delta_h_m.map(|v| (Vec::new(), v)))
            .collect(),
        out.basins.len(),
        out.evaluations,
        &SameBasin {
            rel: SAME_BASIN,
            point: None,
        },
        1.0,
    );
    if search.distinct_basins > 1 {
        warnings.push(format!(
            "the local searches ended in {} different feasible basins (delta h from {:.6} to {:.6} m)",
            search.distinct_basins,
            search.best_values[0],
            search.best_values[search.best_values.len() - 1]
        ));
    }
    out.search = Some(search);
    out.warnings = warnings;
    Ok(out)
}
