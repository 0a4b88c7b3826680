//! Dimensional synthesis with the certified balancing in the loop (issue 36): the linkage's
//! own geometry — link lengths, frame pivots, a tracer point — chosen so that the tracer
//! passes through precision points, each candidate balanced by the family's certified cone
//! program ([`super::synth::optimum`]). The search is the shared one
//! ([`crate::synth::search::constrained`]); this module supplies the geometry
//! ([`scene_at`]), the path error ([`path_error`]) and the front's driver
//! ([`synthesise`]).

use super::file::{Goal, LinkageProblem, LinkageScene};
use super::model::{tip_of, LinkageError};
pub use super::shape::{
    box_margin, frame_pivot, function_error, min_transmission, path_error, path_error_bound,
    stroke, swing, CrankRatio, FunctionSpec, GeometryParam, JointBox, Kind, PathSpec, Requirement,
    ShapeOutcome, ShapePoint, StrokeSpec, SwingSpec, Synthesis, PATH_SAMPLES,
};
use super::shape::{line_offset, with_line_offset, with_pivots};
use super::synth::{optimum, FORCE, MOMENT, TORQUE};
use crate::families::family::Scene;
use crate::geom::P2;
use crate::report::SolveResult;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::minimax::Settings;
use crate::synth::search::constrained::{self, Found, Shape};
use crate::synth::search::SearchEvidence;

/// The scan grid of a candidate's inner program during the search (at most; the file's
/// `accuracy.scan_samples` where smaller): every candidate's optimum is still certified (its
/// peaks refined from the scan, its Lagrangian bound), on a coarser first look for the
/// local maxima; the design found is solved again at the file's settings.
pub const SEARCH_SCAN_SAMPLES: usize = 120;

/// The parameters' values in the scene `sc` with the tracer at `at` (the search's
/// reference, inside the bounds).
pub fn nominal(syn: &Synthesis, sc: &LinkageScene, at: P2) -> Vec<f64> {
    syn.params
        .iter()
        .map(|p| match p.kind {
            Kind::Length { link, .. } => {
                tip_of(sc.linkage.dyads(), sc.crank_length, link).map_or(f64::NAN, |t| t.x)
            }
            Kind::PivotX { link } => frame_pivot(&sc.linkage, link).map_or(f64::NAN, |p| p.x),
            Kind::PivotY { link } => frame_pivot(&sc.linkage, link).map_or(f64::NAN, |p| p.y),
            Kind::LineOffset { link } => line_offset(&sc.linkage, link).unwrap_or(f64::NAN),
            Kind::TracerX => at.x,
            Kind::TracerY => at.y,
        })
        .collect()
}

/// The scene with the parameters at `x` (lengths first, then pivots, then the sliders'
/// offsets from the crank's pivot as it then stands) and the tracer point (the file's `at`
/// where it is not free). Errors where a length or a pivot leaves no linkage (a length ≤ 0).
pub fn scene_at(
    syn: &Synthesis,
    base: &LinkageScene,
    at: P2,
    x: &[f64],
) -> Result<(LinkageScene, P2), LinkageError> {
    let mut sc = base.clone();
    let mut tracer = at;
    let mut pivots: Vec<(usize, P2)> = Vec::new();
    let mut offsets: Vec<(usize, f64)> = Vec::new();
    for (p, &v) in syn.params.iter().zip(x) {
        match p.kind {
            Kind::Length { link, bar } => {
                let old = tip_of(sc.linkage.dyads(), sc.crank_length, link)
                    .ok_or(LinkageError::NoLength { link })?
                    .x;
                sc.linkage = sc.linkage.with_length(link, old, v, bar)?;
                if link == 0 {
                    sc.crank_length = v;
                }
            }
            Kind::PivotX { link } | Kind::PivotY { link } => {
                let i = match pivots.iter().position(|q| q.0 == link) {
                    Some(i) => i,
                    None => {
                        let at = frame_pivot(&sc.linkage, link).unwrap_or_else(P2::zeros);
                        pivots.push((link, at));
                        pivots.len() - 1
                    }
                };
                match p.kind {
                    Kind::PivotX { .. } => pivots[i].1.x = v,
                    _ => pivots[i].1.y = v,
                }
            }
            Kind::LineOffset { link } => offsets.push((link, v)),
            Kind::TracerX => tracer.x = v,
            Kind::TracerY => tracer.y = v,
        }
    }
    if !pivots.is_empty() {
        sc.linkage = with_pivots(&sc.linkage, &pivots)?;
    }
    for (link, e) in offsets {
        sc.linkage = with_line_offset(&sc.linkage, link, e)?;
    }
    Ok((sc, tracer))
}

/// A search's end as a front point of the requirement `req`.
fn point_of(
    req: Requirement,
    found: Found,
    eps: Option<f64>,
    objective: Option<f64>,
) -> ShapePoint {
    ShapePoint {
        held_to: eps.map(|e| req.held_to(e)),
        error: req.named(found.error),
        objective: found.objective.or(objective),
        x: found.x,
        search: found.evidence,
    }
}

/// The field index of the objective's peak, for the goals a shape search can minimise.
pub fn goal_field(g: Goal) -> Option<usize> {
    match g {
        Goal::PeakForce => Some(FORCE),
        Goal::PeakMoment => Some(MOMENT),
        Goal::PeakTorque => Some(TORQUE),
        _ => None,
    }
}

/// The linkage scene as a [`Shape`]: its geometry parameters, its kinematic error and its
/// certified optimum's objective.
pub struct LinkageShape<'a> {
    /// The file's scene.
    pub base: &'a LinkageScene,
    /// The free geometry.
    pub syn: &'a Synthesis,
    /// The kinematic requirement.
    pub req: Requirement<'a>,
    /// The inner program's settings.
    pub settings: Settings,
    bounds: Vec<(f64, f64)>,
}

impl<'a> LinkageShape<'a> {
    /// The shape of the scene `base` with the free geometry `syn`, the requirement `req` and
    /// the inner program's settings.
    pub fn new(
        base: &'a LinkageScene,
        syn: &'a Synthesis,
        req: Requirement<'a>,
        settings: Settings,
    ) -> Self {
        LinkageShape {
            base,
            syn,
            req,
            settings,
            bounds: syn.params.iter().map(|p| p.bounds).collect(),
        }
    }
}

impl Shape for LinkageShape<'_> {
    fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    /// The kinematic error; `None` (not admissible) also where the least transmission
    /// angle is below `min_transmission_angle`, the crank ratio above `max_crank_ratio` or a
    /// joint leaves `joint_box`.
    fn error(&self, x: &[f64]) -> Option<f64> {
        let (sc, at) = scene_at(self.syn, self.base, self.req.tracer(), x).ok()?;
        if let Some(ratio) = &self.syn.max_crank_ratio {
            if ratio.of(&sc.linkage, sc.crank_length)? > ratio.max {
                return None;
            }
        }
        if let Some(b) = &self.syn.joint_box {
            if box_margin(&sc.linkage, sc.crank_length, b)?.value < 0.0 {
                return None;
            }
        }
        if let Some(mu) = self.syn.min_transmission {
            if min_transmission(&sc.linkage)?.value < mu {
                return None;
            }
        }
        self.req.error(&sc.linkage, at)
    }

    /// "the swing error 0.5 deg": the requirement's name and unit.
    fn bound_text(&self, eps: f64) -> String {
        let (what, v, unit) = self.req.named(eps).shown();
        format!("the {what} {v:.6} {unit}")
    }

    /// The peak of the geometry's certified optimum, `None` unless the engine certified
    /// it (`optimal`).
    fn objective(&self, x: &[f64]) -> Option<f64> {
        let (sc, _) = scene_at(self.syn, self.base, self.req.tracer(), x).ok()?;
        let field = goal_field(sc.objective.minimize)?;
        let sol = optimum(&sc, &self.settings).ok()??;
        (sol.status == CwStatus::Optimal).then(|| sol.peaks[field].peak)
    }
}

/// The shape search of the scene `sc`: the least kinematic error (its geometry then
/// balanced: synthesise first, balance afterwards), then for each ε of the front —
/// `front_points` evenly spaced values below `max_error`, and `max_error` — the least
/// certified objective with the kinematic error ≤ ε, each searched from the Halton points
/// and the previous geometry. `Err` when no geometry of the box meets the requirement or
/// none balances.
pub fn synthesise(
    sc: &LinkageScene,
    syn: &Synthesis,
    req: Requirement,
    settings: &Settings,
) -> Result<ShapeOutcome, String> {
    if goal_field(sc.objective.minimize).is_none() || sc.counterweights.is_empty() {
        return Err("a shape search minimises a peak (force, moment or torque) with counterweights to design".into());
    }
    let inner = Settings {
        scan_samples: settings.scan_samples.min(SEARCH_SCAN_SAMPLES),
        ..*settings
    };
    let shape = LinkageShape::new(sc, syn, req, inner);
    let x0 = nominal(syn, sc, req.tracer());
    let inside = x0
        .iter()
        .zip(&shape.bounds)
        .all(|(v, b)| (b.0..=b.1).contains(v));
    let nominal = shape.error(&x0).filter(|_| inside).map(|e| ShapePoint {
        held_to: None,
        x: x0.clone(),
        error: req.named(e),
        objective: shape.objective(&x0),
        search: SearchEvidence::default(),
    });
    let seeds: Vec<Vec<f64>> = nominal.iter().map(|n| n.x.clone()).collect();
    let kin = constrained::least_error(&shape, &seeds, &syn.search).ok_or(
        "no geometry of the box assembles over the whole turn (with the least transmission angle asked)",
    )?;
    let f_kin = shape.objective(&kin.x);
    let kinematic_first = point_of(req, kin, None, f_kin);
    let (e_min, e_max) = (kinematic_first.error.value(), req.max_error());
    if e_min > e_max {
        let (what, v, unit) = req.named(e_min).shown();
        return Err(format!(
            "the least {what} found, {v:.6} {unit}, exceeds {}.max_error",
            req.key()
        ));
    }
    let f_ref = f_kin
        .or(nominal.as_ref().and_then(|n| n.objective))
        .ok_or("the least-error geometry's balancing is not certified")?;
    let n = syn.front_points;
    let mut front: Vec<ShapePoint> = Vec::new();
    let mut seeds = vec![kinematic_first.x.clone()];
    for j in 1..=n + 1 {
        let eps = e_min + (e_max - e_min) * j as f64 / (n + 1) as f64;
        let found = constrained::least_objective(&shape, eps, f_ref, &seeds, &syn.search)
            .ok_or_else(|| {
                format!(
                    "no balanced geometry with {} at most",
                    shape.bound_text(eps)
                )
            })?;
        seeds.push(found.x.clone());
        front.push(point_of(req, found, Some(eps), None));
    }
    Ok(ShapeOutcome {
        parameters: syn.params.iter().map(|p| p.name.clone()).collect(),
        nominal,
        kinematic_first,
        front,
    })
}

/// The linkage's solve through the one driver: with a shape search not yet run, the search
/// first ([`synthesise`]), then the whole solve of its chosen geometry — the scene the
/// report draws — with the search's outcome in [`LinkageProblem::shape`]; the search's time
/// is added to the solve's. A search that finds no geometry leaves the file's geometry
/// solved, with the reason as a warning.
pub fn drive(scene: &Scene, p: &LinkageProblem) -> SolveResult {
    let (Some(syn), Some(req), None) = (&p.synthesis, p.requirement(), &p.shape) else {
        return crate::families::driver::drive(scene, p);
    };
    let t0 = std::time::Instant::now();
    let chosen = synthesise(&p.scene, syn, req, &p.settings).and_then(|out| {
        let x = &out.chosen().ok_or("the front is empty")?.x;
        let (sc, at) = scene_at(syn, &p.scene, req.tracer(), x).map_err(|e| e.to_string())?;
        super::file::check_full_turn(&sc.linkage).map_err(|e| e.message)?;
        Ok(LinkageProblem {
            scene: sc,
            path: p.path.as_ref().map(|path| PathSpec { at, ..path.clone() }),
            shape: Some(out),
            ..p.clone()
        })
    });
    let searched = t0.elapsed().as_secs_f64();
    match chosen {
        Ok(q) => {
            let q = std::sync::Arc::new(q);
            let scene = Scene {
                machine: q.clone(),
                ..scene.clone()
            };
            let mut r = crate::families::driver::drive(&scene, q.as_ref());
            r.timing.solve_s += searched;
            r
        }
        Err(why) => {
            let mut r = crate::families::driver::drive(scene, p);
            r.warnings.push(format!(
                "the shape search found no design: {why}; the file's geometry is solved"
            ));
            r
        }
    }
}

/// The claim of a synthesised design: the geometry is a multistart's (`best_found`, the
/// evidence of the search at `max_error`), its counterweights the certified optimum of that
/// geometry (the inner claim's `optimal`, said in the detail). An inner claim other than
/// `optimal` stands as it is.
pub fn claim(shape: &ShapeOutcome, c: &mut crate::families::driver::Claim) {
    let Some(chosen) = shape.chosen() else { return };
    if c.status == crate::report::Status::Optimal {
        c.status = crate::report::Status::BestFound;
        c.status_detail = Some(format!(
            "the geometry ({} parameters) is the best a multistart found, not proven; the counterweights are the certified optimum (optimal) of that geometry",
            shape.parameters.len()
        ));
        c.search = Some(chosen.search.clone());
    }
    c.method = format!(
        "{}; for the geometry found: {}",
        chosen.search.method, c.method
    );
}
